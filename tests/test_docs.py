"""The docs show the real code: every code block under a `<!-- source: PATH -->` marker in docs/
stands verbatim in that file, and every relative link in the README and docs/ points at a file
that exists."""

import glob
import os
import re

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOCS = sorted(glob.glob(os.path.join(ROOT, "docs", "*.md"))) + [os.path.join(ROOT, "README.md")]
MARKED = re.compile(r"<!-- source: (\S+) -->\n```python\n(.*?)```", re.S)


def test_some_doc_blocks_are_marked():
    assert sum(len(MARKED.findall(open(p, encoding="utf-8").read())) for p in DOCS) >= 3


@pytest.mark.parametrize("path", DOCS, ids=lambda p: os.path.relpath(p, ROOT))
def test_marked_code_is_the_source(path):
    for src, block in MARKED.findall(open(path, encoding="utf-8").read()):
        with open(os.path.join(ROOT, src), encoding="utf-8") as f:
            assert block in f.read(), f"{os.path.relpath(path, ROOT)}: the block marked {src} is not in {src}"


@pytest.mark.parametrize("path", DOCS, ids=lambda p: os.path.relpath(p, ROOT))
def test_relative_links_resolve(path):
    text = open(path, encoding="utf-8").read()
    for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
        if "://" in target or target.startswith("mailto:"):
            continue
        full = os.path.normpath(os.path.join(os.path.dirname(path), target))
        assert os.path.exists(full), f"{os.path.relpath(path, ROOT)} links to {target}, which does not exist"
