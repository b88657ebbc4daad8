"""Reading user text files: UTF-8 only, with a message that points at the offending byte."""

from __future__ import annotations

_UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


def decode_utf8(raw: bytes) -> tuple[str | None, str]:
    """Decode UTF-8 (a leading byte-order mark is dropped).

    Returns:
        (text, "") or (None, problem): the problem names the byte, its offset,
        line and column, ready to follow "file 'x' ".
    """
    if raw.startswith(_UTF16_BOMS):
        return None, "is UTF-16 (it starts with a UTF-16 byte-order mark); save it as UTF-8"
    try:
        return raw.decode("utf-8-sig"), ""
    except UnicodeDecodeError as err:
        offset = err.start
        line = raw.count(b"\n", 0, offset) + 1
        column = offset - (raw.rfind(b"\n", 0, offset) + 1) + 1
        return None, (f"is not UTF-8: byte 0x{raw[offset]:02x} at byte offset {offset} "
                      f"(line {line}, column {column}) cannot be decoded; save the file as UTF-8")
