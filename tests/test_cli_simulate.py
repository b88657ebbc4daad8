"""`springcad simulate` writes a bench record that `springcad fit` reads back."""

from springcad.cli import main
from springcad.fit.data import read_bench_csv
from tests.conftest import template


def test_simulate_then_fit_round_trip(tmp_path, capsys):
    rec = tmp_path / "rec.csv"
    assert main(["simulate", str(template("paper_2xS1")), "--out", str(rec), "--seed", "3"]) == 0
    r = read_bench_csv(rec)
    assert r.n_samples > 10_000 and abs(r.sample_rate_hz - 500) < 1
    assert main(["simulate", str(template("paper_2xS1")), "--out", str(rec)]) == 2  # no silent overwrite
    assert "already exists" in capsys.readouterr().err
    out = tmp_path / "fit"
    assert main(["fit", str(rec), "--out", str(out), "--config", str(template("paper_2xS1")),
                 "--no-plots"]) == 0
    assert (out / "fit.json").exists()
