"""Layout check of a typeset PDF: words printed over each other, from ``pdftotext -bbox``.

poppler's ``pdftotext -bbox`` writes every word of every page with its box (points, origin top
left). Two words collide when the area their boxes share is more than a third of the smaller
box: a column squeezed so far that its header words print over each other, a long key over its
value, two figure labels over each other. Neighbouring words on one line touch or share a sliver
(kerning, a tight table inset) and stay well below a third.
"""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

#: Share of the smaller box two words may have in common before they count as overprinted.
OVERLAP_SHARE = 1.0 / 3.0

_PAGE = re.compile(r"<page\b[^>]*>(.*?)</page>", re.S)
_WORD = re.compile(
    r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="([\d.]+)">(.*?)</word>', re.S
)


@dataclass(frozen=True)
class Word:
    """A word on a page and its box (points from the top left)."""

    text: str
    x0: float
    y0: float
    x1: float
    y1: float

    @property
    def area(self) -> float:
        return max(self.x1 - self.x0, 0.0) * max(self.y1 - self.y0, 0.0)


@dataclass(frozen=True)
class Collision:
    """Two words on ``page`` (1-based) whose boxes share ``share`` of the smaller one."""

    page: int
    first: Word
    second: Word
    share: float

    def __str__(self) -> str:
        return (
            f"page {self.page}: {self.first.text!r} over {self.second.text!r} "
            f"({self.share:.0%} of the smaller box)"
        )


def have_pdftotext() -> bool:
    """Whether poppler's ``pdftotext`` is on the PATH."""
    return shutil.which("pdftotext") is not None


def pages_words(pdf: Path) -> list[list[Word]]:
    """The words of every page of ``pdf``, with their boxes (``pdftotext -bbox``)."""
    out = subprocess.run(
        ["pdftotext", "-bbox", str(pdf), "-"], capture_output=True, text=True, check=True
    ).stdout
    pages = []
    for body in _PAGE.findall(out):
        words = [
            Word(html.unescape(t), float(a), float(b), float(c), float(d))
            for a, b, c, d, t in _WORD.findall(body)
        ]
        pages.append(words)
    return pages


def collisions(pages: list[list[Word]], share: float = OVERLAP_SHARE) -> list[Collision]:
    """Pairs of words on a page whose boxes overlap by more than ``share`` of the smaller box.

    Words are swept in order of their left edge, so a page of a few thousand words costs a few
    milliseconds rather than every pair.
    """
    found = []
    for number, words in enumerate(pages, start=1):
        ordered = sorted((w for w in words if w.area > 0), key=lambda w: w.x0)
        for i, a in enumerate(ordered):
            for b in ordered[i + 1 :]:
                if b.x0 >= a.x1:
                    break
                w = min(a.x1, b.x1) - max(a.x0, b.x0)
                h = min(a.y1, b.y1) - max(a.y0, b.y0)
                if w <= 0 or h <= 0:
                    continue
                common = w * h / min(a.area, b.area)
                if common > share:
                    found.append(Collision(number, a, b, common))
    return found
