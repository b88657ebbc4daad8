"""Just enough PDF reading to list the text strings matplotlib writes (tests only).

matplotlib writes text as ``[(...) kern (...)] TJ`` or ``(...) Tj`` in
Flate-compressed content streams; Type 42 fonts use two-byte (UTF-16BE) codes.
"""

import re
import zlib

_STRING = re.compile(rb"\((?:\\.|[^\\)])*\)")


def _unescape(raw: bytes) -> bytes:
    out, i = bytearray(), 0
    while i < len(raw):
        c = raw[i]
        if c == 0x5C and i + 1 < len(raw):  # backslash
            nxt = raw[i + 1]
            if 0x30 <= nxt <= 0x37:
                j = i + 1
                while j < min(i + 4, len(raw)) and 0x30 <= raw[j] <= 0x37:
                    j += 1
                out.append(int(raw[i + 1:j], 8) & 0xFF)
                i = j
                continue
            out.append({ord("n"): 10, ord("r"): 13, ord("t"): 9, ord("b"): 8,
                        ord("f"): 12}.get(nxt, nxt))
            i += 2
            continue
        out.append(c)
        i += 1
    return bytes(out)


def _decode(b: bytes) -> str:
    if len(b) % 2 == 0 and b[:1] == b"\x00":
        return b.decode("utf-16-be", errors="replace")
    return b.decode("latin-1")


def pdf_strings(data: bytes) -> list[str]:
    """Every text-showing operation's string, kerning pieces joined."""
    out = []
    for stream in re.findall(rb"stream\r?\n(.*?)\r?\nendstream", data, re.S):
        try:
            content = zlib.decompress(stream)
        except zlib.error:
            content = stream
        for m in re.finditer(rb"\[(.*?)\]\s*TJ|(\((?:\\.|[^\\)])*\))\s*Tj", content, re.S):
            body = m.group(1) if m.group(1) is not None else m.group(2)
            pieces = [_unescape(s[1:-1]) for s in _STRING.findall(body)]
            out.append("".join(_decode(p) for p in pieces))
    return out
