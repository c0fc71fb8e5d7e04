# This file is part of the lidarsgm module (an OpenCV extra module).
"""The fenced code blocks of README.md and doc/*.md, as the snippet tests run them."""
import glob
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
FENCE = re.compile(r"^```(\S*)\s*$")


def doc_files():
    """README.md and doc/*.md, as paths relative to the repository root."""
    files = ["README.md"] + sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "doc", "*.md")))
    return [f for f in files if os.path.isfile(os.path.join(ROOT, f))]


def blocks(path, language):
    """The `language` blocks of one Markdown file: a list of (first code line, 1-based; code)."""
    found, lang, start, lines = [], None, 0, []
    with open(os.path.join(ROOT, path), encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            m = FENCE.match(line)
            if lang is None:
                if m:
                    lang, start, lines = m.group(1), number + 1, []
            elif m and not m.group(1):
                if lang == language:
                    found.append((start, "".join(lines)))
                lang = None
            else:
                lines.append(line)
    if lang is not None:
        raise ValueError("%s: the block opened before line %d is not closed" % (path, start))
    return found
