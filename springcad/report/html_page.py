"""Self-contained HTML pages: one style, images inlined, a small Markdown subset.

Every ``report.html`` (build, fit, paper) is one file a person opens in a
browser or sends on: images are base64 data, the style is inline, nothing is
fetched from the network. :func:`markdown_html` turns the Markdown the reports
already write (headings, pipe tables, bullet lists, images, paragraphs,
``**bold**``, ``*italic*``, ```code```) into HTML, so a report is written once.
"""

from __future__ import annotations

import base64
import html
import re
from pathlib import Path

CSS = """
body{font-family:system-ui,Segoe UI,Helvetica,Arial,sans-serif;margin:2em auto;max-width:1100px;
color:#222;line-height:1.35;padding:0 1em}
h1{margin-bottom:.2em}h2{border-bottom:2px solid #ddd;padding-bottom:.15em;margin-top:1.6em}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:.25em .6em}
th{background:#f2f2f2;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums}
.verdict{padding:.8em 1.2em;border-radius:6px;font-size:1.25em;font-weight:600}
.ok{background:#e3f4e1;border:2px solid #3a8d34}.bad{background:#fbe3e1;border:2px solid #b8322a}
.warn{background:#fdf3d8;border:2px solid #b88a1a}
.fail{color:#b8322a;font-weight:600}.figs{display:flex;flex-wrap:wrap;gap:1em}
figure{margin:0}img{max-width:100%;height:auto}figcaption{font-size:.9em;color:#555}
.thumb{border:1px solid #ccc;background:#fff;width:260px;height:185px;object-fit:contain}
code{background:#f4f4f4;padding:0 .2em}
.scroll{overflow-x:auto}.bom td{vertical-align:top}.bom a{margin-right:.4em}
.narrow{display:none;font-size:.9em;color:#555;font-style:italic}
@media (max-width:700px){body{margin:1em auto;font-size:.95em}.thumb{width:100%;height:auto}
.narrow{display:block}
td,th{padding:.2em .35em}.bom td,.bom th{white-space:nowrap}}
"""

_BULLET = re.compile(r"^\s*[-*]\s+")
_MIME = {".png": "image/png", ".svg": "image/svg+xml", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}


def img_tag(path: Path, alt: str, cls: str = "", width: int | None = None) -> str:
    """An ``<img>`` whose picture is inline data (no file beside the page needed)."""
    path = Path(path)
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    extra = (f" class='{cls}'" if cls else "") + (f" width='{width}'" if width else "")
    return (f"<img alt='{html.escape(alt)}' src='data:{_MIME[path.suffix.lower()]};base64,"
            f"{data}'{extra}/>")


def page(title: str, body: str) -> str:
    """A complete HTML document with the common style."""
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            "<meta name='viewport' content='width=device-width, initial-scale=1'>"
            f"<title>{html.escape(title)}</title><style>{CSS}</style></head><body>\n"
            f"{body}\n</body></html>\n")


def inline_md(text: str) -> str:
    """Escape ``text`` and render ``**bold**``, ``*italic*`` and ```code```."""
    text = html.escape(text)
    text = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", text)
    text = re.sub(r"(?<![\w*])\*(?!\s)(.+?)(?<!\s)\*(?![\w*])", r"<i>\1</i>", text)
    return re.sub(r"`(.+?)`", r"<code>\1</code>", text)


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def markdown_html(text: str, image_dir: Path | None = None) -> str:
    """HTML of the Markdown subset the reports write.

    Args:
        text: Markdown.
        image_dir: folder of the images ``![alt](file)`` names; they are inlined.
            An image that is not there becomes its alt text.
    """
    out: list[str] = []
    lines = text.splitlines()
    i = 0
    para: list[str] = []

    def flush():
        if para:
            out.append(f"<p>{inline_md(' '.join(para))}</p>")
            para.clear()

    while i < len(lines):
        line = lines[i].rstrip()
        m_head = re.match(r"^(#{1,4})\s+(.*)$", line)
        m_img = re.match(r"^!\[(.*?)\]\((.*?)\)\s*$", line)
        if not line.strip():
            flush()
        elif m_head:
            flush()
            n = len(m_head.group(1))
            out.append(f"<h{n}>{inline_md(m_head.group(2))}</h{n}>")
        elif m_img:
            flush()
            alt, name = m_img.groups()
            path = (Path(image_dir) / name) if image_dir is not None else None
            out.append(f"<figure>{img_tag(path, alt)}<figcaption>{html.escape(alt)}"
                       "</figcaption></figure>" if path is not None and path.is_file()
                       else f"<p>[{html.escape(alt)}]</p>")
        elif line.lstrip().startswith("|") and i + 1 < len(lines) and \
                re.match(r"^\s*\|?\s*:?-{3,}", lines[i + 1]):
            flush()
            head = "".join(f"<th>{inline_md(c)}</th>" for c in _cells(line))
            rows = []
            i += 2
            while i < len(lines) and lines[i].lstrip().startswith("|"):
                rows.append("<tr>" + "".join(f"<td>{inline_md(c)}</td>" for c in _cells(lines[i]))
                            + "</tr>")
                i += 1
            out.append(f"<table><tr>{head}</tr>{''.join(rows)}</table>")
            continue
        elif _BULLET.match(line):
            flush()
            items = []
            while i < len(lines) and _BULLET.match(lines[i]):
                item = _BULLET.sub("", lines[i])
                items.append(f"<li>{inline_md(item)}</li>")
                i += 1
            out.append(f"<ul>{''.join(items)}</ul>")
            continue
        else:
            para.append(line.strip())
        i += 1
    flush()
    return "\n".join(out)
