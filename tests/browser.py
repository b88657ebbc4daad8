"""Open a report in headless Chromium (Debian's ``chromium`` package) and take a screenshot."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
needs_chromium = pytest.mark.skipif(not Path(CHROMIUM).exists(),
                                    reason="Debian's chromium package is not installed")


def screenshot(page: Path, tmp_path: Path, size=(1200, 2000)):
    """The page as Chromium draws it: an (H, W, 3) float array."""
    import numpy as np
    from PIL import Image

    shot = tmp_path / f"{page.stem}.png"
    cmd = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           "--no-first-run", f"--user-data-dir={tmp_path / 'profile'}", f"--screenshot={shot}",
           f"--window-size={size[0]},{size[1]}", page.as_uri()]
    subprocess.run(cmd, capture_output=True, timeout=120, check=False)
    assert shot.is_file(), "chromium wrote no screenshot"
    img = np.asarray(Image.open(shot).convert("RGB")).astype(float)
    assert img.shape[:2] == (size[1], size[0])
    return img


def assert_rendered(img) -> None:
    """Not blank: many distinct colours and real contrast (text, tables, images)."""
    import numpy as np

    assert img.std() > 20
    assert len(np.unique(img.reshape(-1, 3)[::7], axis=0)) > 200


def assert_self_contained(text: str) -> None:
    """No network: every image is inline data, links only to local files."""
    assert not re.search(r"(src|href)=['\"]https?:", text)
    assert all(s.startswith("data:") for s in re.findall(r"src=['\"]([^'\"]+)", text))


def headings(text: str, level: int = 2) -> list[str]:
    return [re.sub(r"<[^>]+>", "", h) for h in re.findall(rf"<h{level}>(.*?)</h{level}>", text)]
