import os
import subprocess
import sys

from . import MUTATIONS

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT = ["-m", "not slow", "--deselect", "tests/test_golden.py", "-q", "-p", "no:cacheprovider"]


def run(name, args):
    """pytest with the mutation applied; (exit code, the failed tests)."""
    env = dict(os.environ, TISPH_MUTATION=name)
    r = subprocess.run([sys.executable, "-m", "pytest", "-p", "tests.mutations.plugin", *(args or DEFAULT),
                        "-rf", "--no-header"], cwd=ROOT, env=env, capture_output=True, text=True)
    failed = sorted({line.split()[1].split("[")[0] for line in r.stdout.splitlines() if line.startswith("FAILED ")})
    return r.returncode, failed


def main(argv):
    if not argv:
        for k, v in MUTATIONS.items():
            print(f"{k:22s} {v[3]}")
        return 0
    if argv[0] == "--all":
        out = argv[argv.index("--out") + 1] if "--out" in argv else None
        lines = ["| mutation | what it breaks | tests (not golden) that fail |", "|---|---|---|"]
        for k, v in MUTATIONS.items():
            code, failed = run(k, None)
            lines.append(f"| {k} | {v[3]} | {', '.join(failed) if failed else '**none**'} |")
            print(lines[-1], flush=True)
        if out:
            with open(out, "w") as f:
                f.write("\n".join(lines) + "\n")
        return 0
    code, failed = run(argv[0], argv[1:])
    print("\n".join(failed) or "no test failed")
    return 0


sys.exit(main(sys.argv[1:]))
