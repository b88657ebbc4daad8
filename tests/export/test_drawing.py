

def test_packaged_title_block_is_the_template():
    """The copy shipped in the package (for non-editable installs) equals templates/."""
    from pathlib import Path

    import springcad

    repo = Path(springcad.__file__).resolve().parents[1]
    packaged = repo / "springcad" / "data" / "drawing_title_block.toml"
    assert packaged.read_text() == (repo / "templates" / "drawing_title_block.toml").read_text()
