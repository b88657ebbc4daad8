"""The suite's own xdist schedule (tests/conftest.py): the modules it groups exist, and a
group's tests share one scope while every other test is a scope of its own."""

from tests.conftest import ROOT, SHARED_WORK


def test_shared_work_names_existing_test_modules():
    """A renamed or moved module would silently leave its group (and build its shared
    fixture on both workers again)."""
    for module in SHARED_WORK:
        assert (ROOT / module).is_file(), module
        assert module.startswith("tests/") and module.rsplit("/", 1)[1].startswith("test_")


def test_groups_are_scopes_and_other_tests_their_own():
    import pytest

    xdist_scheduler = pytest.importorskip("xdist.scheduler")
    from tests.conftest import pytest_xdist_make_scheduler

    class Config:
        class option:
            loadscopereorder = True
            tx = ["popen"] * 2
            numprocesses = 2
            dist = "load"

        def getvalue(self, name):
            return getattr(self.option, name)

    sched = pytest_xdist_make_scheduler(Config(), None)
    assert isinstance(sched, xdist_scheduler.LoadScopeScheduling)
    assert not Config.option.loadscopereorder  # the collection's order is kept
    a, b = "tests/export/test_cli_build.py::x", "tests/report/test_html_build_report.py::y"
    assert sched._split_scope(a) == sched._split_scope(b) == "s1_cli_build"
    lone = "tests/test_units.py::test_factors"
    assert sched._split_scope(lone) == lone
