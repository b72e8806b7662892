"""Shared helpers of the report tests: PNG sizes, blank-image checks, compiling LaTeX."""

from __future__ import annotations

import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np

#: An image is "not blank" when the standard deviation of its grey levels (0..1) is above
#: this: a white page with one line of text already has ~0.03, an empty page 0.
BLANK_STD = 0.01

LATEXMK = shutil.which("latexmk")
PDFTOPPM = shutil.which("pdftoppm")


def png_size(path) -> tuple[int, int]:
    """(width, height) from the IHDR chunk of a PNG file; fails if it is not a PNG."""
    data = Path(path).read_bytes()[:24]
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG file"
    assert data[12:16] == b"IHDR", f"{path}: no IHDR chunk"
    return struct.unpack(">II", data[16:24])


def grey_std(path) -> float:
    """Standard deviation of the grey levels of a PNG (matplotlib.image reads it as floats)."""
    import matplotlib.image as mpimg

    img = mpimg.imread(str(path))
    grey = img[..., :3].mean(axis=-1) if img.ndim == 3 else img
    return float(np.std(grey))


def latexmk(tex_dir: Path, name: str) -> tuple[int, str]:
    """Compile ``tex_dir/name.tex`` with latexmk; return (exit code, log text)."""
    proc = subprocess.run([LATEXMK, "-pdf", "-interaction=nonstopmode", "-halt-on-error",
                           f"{name}.tex"], cwd=tex_dir, capture_output=True, timeout=600,
                          stdin=subprocess.DEVNULL)
    log = tex_dir / f"{name}.log"
    return proc.returncode, log.read_text(errors="replace") if log.exists() else ""
