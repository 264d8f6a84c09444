"""Files written atomically: to a temporary name in the same folder, then renamed."""
from __future__ import annotations

import csv
import io as _io
import json
import math
import os
import tempfile
from contextlib import contextmanager


_UMASK = os.umask(0)
os.umask(_UMASK)


class OutputError(RuntimeError):
    """The output folder or a file in it cannot be written."""


def ensure_dir(path):
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise OutputError(f"cannot create output folder {path!r}: {e.strerror}") from None
    if not os.access(path, os.W_OK):
        raise OutputError(f"output folder {path!r} is not writable")
    return path


@contextmanager
def atomic_path(path, suffix=None):
    """Yield a temporary path next to `path`; rename it onto `path` only if the block succeeds."""
    d = os.path.dirname(os.path.abspath(path))
    base = os.path.basename(path)
    sfx = suffix if suffix is not None else os.path.splitext(base)[1]
    fd, tmp = tempfile.mkstemp(prefix="." + base + ".", suffix=".part" + sfx, dir=d)
    os.close(fd)
    os.chmod(tmp, 0o666 & ~_UMASK)  # mkstemp makes 0600; outputs get the usual permissions
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def write_bytes(path, data: bytes):
    try:
        with atomic_path(path) as tmp:
            with open(tmp, "wb") as f:
                f.write(data)
                f.flush()
                os.fsync(f.fileno())
    except OSError as e:
        raise OutputError(f"cannot write {path!r}: {e.strerror}") from None


def write_text(path, text: str):
    write_bytes(path, text.encode())


def _finite(obj):
    """NaN/Inf -> None: strict JSON has no NaN, and a missing value reads as null elsewhere."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def write_json(path, obj):
    write_text(path, json.dumps(_finite(obj), indent=2, allow_nan=False) + "\n")


def write_csv(path, header, rows):
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow([f"{v:.7g}" if isinstance(v, float) else v for v in r])
    write_text(path, buf.getvalue())


def read_csv(path):
    """Header and columns (as float lists) of a CSV written by write_csv."""
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h: [float(r[k]) for r in rows[1:]] for k, h in enumerate(header)}
    return header, cols
