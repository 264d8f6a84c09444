import os
import subprocess
import sys
import tempfile

from . import MUTATIONS

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT = ["-m", "not slow", "--deselect", "tests/engine/test_golden.py", "-q", "-p", "no:cacheprovider"]


def run(name, args):
    """pytest with the mutation applied; (exit code, the tests failed on an assertion, the tests
    failed on another exception). A failure that is not an assertion may be the mutation breaking
    the code rather than the physics (a compile error), so it is listed apart."""
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "failed.tsv")
        env = dict(os.environ, TISPH_MUTATION=name, TISPH_MUTATION_REPORT=report)
        r = subprocess.run(
            [sys.executable, "-m", "pytest", "-p", "tests.mutations.plugin", *(args or DEFAULT), "--no-header"],
            cwd=ROOT,
            env=env,
            capture_output=True,
            text=True,
        )
        rows = [line.rstrip("\n").split("\t") for line in open(report)] if os.path.exists(report) else []
    asserted = sorted({t for t, kind in rows if kind == "assertion"})
    other = sorted({f"{t} ({kind})" for t, kind in rows if kind != "assertion" and t not in asserted})
    return r.returncode, asserted, other


def main(argv):
    if not argv:
        for k, v in MUTATIONS.items():
            print(f"{k:22s} {v[3]}")
        return 0
    if argv[0] == "--all":
        out = argv[argv.index("--out") + 1] if "--out" in argv else None
        lines = [
            "| mutation | what it breaks | tests (not golden) that fail on an assertion | on another error |",
            "|---|---|---|---|",
        ]
        for k, v in MUTATIONS.items():
            code, failed, other = run(k, None)
            lines.append(
                f"| {k} | {v[3]} | {', '.join(failed) if failed else '**none**'} | {', '.join(other) or '-'} |"
            )
            print(lines[-1], flush=True)
        if out:
            with open(out, "w") as f:
                f.write("\n".join(lines) + "\n")
        return 0
    code, failed, other = run(argv[0], argv[1:])
    print("\n".join(failed) or "no test failed on an assertion")
    if other:
        print("failed on another error:\n" + "\n".join(other))
    return 0


sys.exit(main(sys.argv[1:]))
