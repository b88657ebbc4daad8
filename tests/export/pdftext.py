"""Read drawings back with poppler (a second reader, not matplotlib): text and word boxes.

``pdftotext`` and ``pdftoppm`` (poppler-utils) are required by the drawing tests.
Units: mm, sheet origin at the top left (PDF readers' convention).
"""

import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

MM_PER_PT = 25.4 / 72.0
_WORD = re.compile(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="([\d.]+)">(.*?)</word>')
_PAGE = re.compile(r'<page width="([\d.]+)" height="([\d.]+)">')


def _poppler(tool: str) -> str:
    path = shutil.which(tool)
    if path is None:
        raise RuntimeError(f"{tool} (poppler-utils) is needed to read the drawings back")
    return path


def pdf_text(path: Path) -> str:
    """All text of a PDF, one text run per line (``pdftotext -raw``)."""
    out = subprocess.run([_poppler("pdftotext"), "-raw", str(path), "-"], capture_output=True,
                         text=True, check=True)
    return out.stdout


@dataclass(frozen=True)
class Word:
    """One word and its box on the page (mm, origin top left, y down)."""

    text: str
    x0: float
    y0: float
    x1: float
    y1: float


def pdf_pages(path: Path) -> int:
    """Number of pages (``pdfinfo``)."""
    out = subprocess.run([_poppler("pdfinfo"), str(path)], capture_output=True, text=True,
                         check=True).stdout
    return int(re.search(r"^Pages:\s+(\d+)", out, re.M).group(1))


def pdf_words(path: Path, page: int = 1) -> tuple[list[Word], tuple[float, float]]:
    """Every word of a page with its box, and the page size (mm), from ``pdftotext -bbox``."""
    import html

    out = subprocess.run([_poppler("pdftotext"), "-bbox", "-f", str(page), "-l", str(page),
                          str(path), "-"], capture_output=True, text=True, check=True).stdout
    w, h = (float(v) * MM_PER_PT for v in _PAGE.search(out).groups())
    words = [Word(html.unescape(m.group(5)), *(float(v) * MM_PER_PT for v in m.groups()[:4]))
             for m in _WORD.finditer(out)]
    return words, (w, h)


def pdf_png(path: Path, out_prefix: Path, dpi: int, page: int = 1) -> Path:
    """Render a page with ``pdftoppm`` and return the PNG path."""
    subprocess.run([_poppler("pdftoppm"), "-png", "-r", str(dpi), "-f", str(page), "-l",
                    str(page), "-singlefile", str(path), str(out_prefix)], check=True)
    return Path(f"{out_prefix}.png")


def pdf_without_text(src: Path, dst: Path) -> Path:
    """A copy of a matplotlib PDF with every text object (BT ... ET) removed from its pages.

    Each page content stream is rewritten in place: the new (shorter) Flate stream is
    padded after ``endstream`` and its length object padded with spaces, so every byte
    offset of the cross-reference table stays valid.
    """
    data = Path(src).read_bytes()
    for m in re.finditer(rb"/Contents (\d+) 0 R", data):
        data = _strip_text(data, int(m.group(1)))
    Path(dst).write_bytes(data)
    return Path(dst)


def _strip_text(data: bytes, contents: int) -> bytes:
    """``data`` with the text objects of one page content stream (object ``contents``)
    removed, every byte offset kept."""
    import zlib

    head = re.search(rb"\n%d 0 obj\n<< /Length (\d+) 0 R /Filter /FlateDecode >>\nstream\n"
                     % contents, data)
    len_obj = int(head.group(1))
    len_m = re.search(rb"\n%d 0 obj\n(\d+)\nendobj" % len_obj, data)
    old_len = int(len_m.group(1))
    start = head.end()
    content = zlib.decompress(data[start:start + old_len])
    # a text object: "BT\n ... \nET\n" (embedded TrueType) or "BT /F1 10 Tf ... Tj ET\n" (core font)
    stripped = re.sub(rb"(?<![^\n ])BT[\n ].*?[\n ]ET\n", b"", content, flags=re.S)
    new = zlib.compress(stripped, 9)
    assert len(new) <= old_len and len(str(len(new))) <= len(len_m.group(1))
    tail_at = start + old_len
    assert data[tail_at:tail_at + 10] == b"\nendstream"
    out = (data[:start] + new + b"\nendstream" + b" " * (old_len - len(new))
           + data[tail_at + 10:])
    num = str(len(new)).encode().rjust(len(len_m.group(1)))
    a, b = len_m.span(1)
    return out[:a] + num + out[b:]
