"""A drawing PDF uses the core font Helvetica (nothing embedded) when every text is in its
character set, and embeds DejaVu Sans when one is not; poppler reads the text back either way."""

import shutil
import subprocess

import pytest

from pdftext import pdf_text
from springcad.export.sheet import Sheet

pytestmark = pytest.mark.skipif(shutil.which("pdffonts") is None, reason="needs poppler-utils")


def fonts(path) -> list[tuple[str, str]]:
    """(font name, embedded yes/no) of each font of a PDF (``pdffonts``, a second reader)."""
    out = subprocess.run(["pdffonts", str(path)], capture_output=True, text=True,
                         check=True).stdout.splitlines()[2:]
    return [(line.split()[0], line.split()[-5]) for line in out]


def write(tmp_path, texts):
    sheet = Sheet()
    for k, s in enumerate(texts):
        sheet.text(50.0, 50.0 + 12.0 * k, s)
    pdf = tmp_path / "sheet.pdf"
    sheet.save(pdf)
    return pdf


def test_latin_texts_use_the_core_font(tmp_path, caplog):
    texts = ["7× Ø1.5 E7 THRU", "11 ±0.01", "0.2 x 45°", "Ra 0.8 µm"]
    pdf = write(tmp_path, texts)
    assert fonts(pdf) == [("Helvetica", "no")]
    assert not [r for r in caplog.records if "findfont" in r.getMessage()]  # no font lookups
    read = pdf_text(pdf)
    assert all(t in read for t in texts), read


def test_a_text_outside_the_core_set_embeds_dejavu(tmp_path):
    texts = ["theta θ ≤ 14°", "plain"]
    pdf = write(tmp_path, texts)
    names = fonts(pdf)
    assert names and all("DejaVuSans" in n and emb == "yes" for n, emb in names), names
    read = pdf_text(pdf)
    assert all(t in read for t in texts), read
