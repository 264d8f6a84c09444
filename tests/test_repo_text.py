"""The repository speaks to users: no words about how it was developed (stop or issue numbers,
sessions, rounds of work, commit hashes as history) in any tracked text file, and a README that
is a user's guide of at most 300 lines."""

import os
import re
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

PROCESS = re.compile(
    r"\bstops? \d+\b|\bissues? #?\d+\b|\b(this|that|last|next|previous|earlier|each|every) (session|stop|round)\b"
    r"|\brounds? of (work|review)\b|\bsessions? \d+\b",
    re.I,
)
# A bare hexadecimal word of 7 to 12 characters with a digit and a letter: a commit named as
# history. Colours (#1f77b4), 0x literals and a hash given as a command's argument (--against X) pass.
HASH = re.compile(r"(?<![#\w/.-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,12}(?![\w/])")
# Tools of the machine the work was done on: a reader cannot run them, so a figure is reproduced
# with the package's own commands (python -m tisph.bench ...) or public ones.
LOCAL_TOOLS = re.compile(r"\bfarm-(bench|studio)\b")
TEXT = (".py", ".md", ".toml", ".txt", ".cfg", ".ini", ".sh", "")


def tracked_files():
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True, check=True).stdout
        names = out.split()
    except (OSError, subprocess.CalledProcessError):  # not a checkout: every file under the root
        names = [
            os.path.relpath(os.path.join(d, f), ROOT)
            for d, ds, fs in os.walk(ROOT)
            for f in fs
            if not any(p.startswith(".") or p in ("renders", "build") for p in d.split(os.sep))
        ]
    return [
        n
        for n in names
        if os.path.splitext(n)[1] in TEXT
        and not n.startswith("tests/golden/states")
        and os.path.isfile(os.path.join(ROOT, n))
    ]


def offending_lines(pattern):
    hits = []
    for name in tracked_files():
        if name == "tests/test_repo_text.py":
            continue
        with open(os.path.join(ROOT, name), encoding="utf-8", errors="replace") as f:
            for k, line in enumerate(f, 1):
                for m in pattern.finditer(line):
                    if pattern is HASH and re.search(r"--against\s+" + m.group(0), line):
                        continue
                    hits.append(f"{name}:{k}: {m.group(0)!r} in {line.strip()[:100]}")
    return hits


@pytest.mark.parametrize("pattern", [PROCESS, HASH, LOCAL_TOOLS], ids=["process words", "commit hashes", "local tools"])
def test_no_words_about_how_the_work_was_done(pattern):
    hits = offending_lines(pattern)
    assert not hits, "words about the project's history in tracked files:\n" + "\n".join(hits[:40])


def test_the_pattern_catches_what_it_names():
    # the examples are built here so that this file does not hold the words it looks for
    for text in (
        "measured at st" + "op 24",
        "Iss" + "ue 17 asked",
        "this" + " session",
        "in this" + " round",
        "at b06b2d7 the",
    ):
        assert PROCESS.search(text) or HASH.search(text), text
    for text in ("the stop time", "--against 5046442", "colour #1f77b4", "a stopping criterion", "0x7fa6"):
        assert not (PROCESS.search(text) or (HASH.search(text) and "--against" not in text)), text


def test_readme_is_a_guide():
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        lines = f.read().splitlines()
    assert len(lines) <= 300, f"README.md has {len(lines)} lines"
    head = " ".join(lines[:20])
    assert "tisph run beach" in head and "python -m tisph.scenes.beach" in head
    for section in ("Requirements", "Scenes", "Validation", "docs/"):
        assert any(section in line for line in lines), section
