"""Files written atomically: to a temporary name in the same folder, then renamed."""

from __future__ import annotations

import csv
import glob
import io as _io
import json
import math
import os
import tempfile
from contextlib import contextmanager

import numpy as np

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
        with atomic_path(path) as tmp, open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
    except OSError as e:
        raise OutputError(f"cannot write {path!r}: {e.strerror}") from None


def write_text(path, text: str):
    write_bytes(path, text.encode())


def json_safe(obj):
    """NaN/Inf -> None: strict JSON has no NaN, and a missing value reads as null elsewhere."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    return obj


def write_json(path, obj):
    write_text(path, json.dumps(json_safe(obj), indent=2, allow_nan=False) + "\n")


def write_csv(path, header, rows):
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow([f"{float(v):.9g}" if isinstance(v, (float, np.floating)) else v for v in r])
    write_text(path, buf.getvalue())


def write_station_rows(path, stations, rows):
    """A bed's history: rows (t, a value at each station), the header t, x<station>... (m)."""
    write_csv(path, ("t",) + tuple(f"x{x:.3f}" for x in stations), rows)


def read_station_rows(path):
    """(times, the stations' x, the values as an array, one row a time) of write_station_rows's CSV."""
    header, cols = read_csv(path)
    return (
        np.array(cols["t"]),
        np.array([float(h[1:]) for h in header[1:]]),
        np.array([cols[h] for h in header[1:]]).T.reshape(len(cols["t"]), len(header) - 1),
    )


def read_csv(path):
    """Header and columns (as float lists) of a CSV written by write_csv."""
    with open(path) as f:
        rows = list(csv.reader(f))
    header = rows[0]
    cols = {h: [float(r[k]) for r in rows[1:]] for k, h in enumerate(header)}
    return header, cols


# ---------------------------------------------------------------------------- HDF5 snapshots
SNAPSHOT_FIELDS = {  # solver member -> (dataset name, XDMF attribute type)
    "x": ("position", None),
    "v": ("velocity", "Vector"),
    "rho": ("density", "Scalar"),
    "p": ("pressure", "Scalar"),
    "m": ("mass", "Scalar"),
    "kind": ("kind", "Scalar"),
    "mat": ("material", "Scalar"),
    "id": ("id", "Scalar"),
    "c": ("concentration", "Scalar"),
}
# what each dataset's numbers mean, written into every snapshot (and docs/scenes.md)
SNAPSHOT_UNITS = {
    "position": "m",
    "velocity": "m/s",
    "density": "kg/m3",
    "pressure": "Pa",
    "mass": "kg per metre of width (2D)",
    "kind": "code (kind_codes)",
    "material": "index (material_names)",
    "id": "particle number",
    "concentration": "volume fraction",
}
KIND_CODES = (
    "0 fluid (water or particle sand), 1 wall, 2 paddle (a moving wall), 3 bed (a bed-load bed's "
    "boundary), -1 left the domain, -2 left through an outflow, -3 removed as spray (numerics.spray_density)"
)
OPTIONAL = ("c",)  # members only some cases carry (c: suspended sand); snapshots and frames take them there


def _pad3(a):
    """(N, 2) -> (N, 3) with z = 0: ParaView reads 3-component points and vectors."""
    return np.column_stack([a, np.zeros(len(a), a.dtype)]) if a.ndim == 2 and a.shape[1] == 2 else a


def write_snapshot(path, state: dict, attrs: dict):
    """One HDF5 file: every particle field (ordered by particle id) plus run attributes."""
    import h5py

    try:
        with atomic_path(path) as tmp, h5py.File(tmp, "w") as f:
            for k, a in state.items():
                name = SNAPSHOT_FIELDS.get(k, (k, None))[0]
                d = f.create_dataset(name, data=_pad3(np.asarray(a)))
                if name in SNAPSHOT_UNITS:
                    d.attrs["units"] = SNAPSHOT_UNITS[name]
                if name == "kind":
                    d.attrs["codes"] = KIND_CODES
                if name == "material" and "material_names" in attrs:
                    d.attrs["codes"] = attrs["material_names"]
            f.attrs["kind_codes"] = KIND_CODES
            for k, v in attrs.items():
                f.attrs[k] = v
    except OSError as e:
        raise OutputError(f"cannot write {path!r}: {e}") from None


def load(path):
    """Read a snapshot or checkpoint: (arrays, attributes), arrays as NumPy, points (N, 2).

    Raises OutputError with the file name when the file is missing, truncated or not HDF5.
    """
    import h5py

    try:
        with h5py.File(path, "r") as f:
            arrays = {k: f[k][()] for k in f if isinstance(f[k], h5py.Dataset)}
            groups = {k: {kk: f[k][kk][()] for kk in f[k]} for k in f if isinstance(f[k], h5py.Group)}
            attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
    except FileNotFoundError:
        raise OutputError(f"{path!r} does not exist") from None
    except OSError as e:
        raise OutputError(f"{path!r} is not a readable tisph HDF5 file ({e})") from None
    for k in ("position", "velocity"):
        if k in arrays and arrays[k].ndim == 2 and arrays[k].shape[1] == 3:
            arrays[k] = arrays[k][:, :2]
    arrays.update(groups)
    return arrays, attrs


def snapshot_files(path):
    """The snapshots of a run folder in time order (numbered files only, not last_good.h5), or
    [path] for a file."""
    if os.path.isfile(path):
        return [path]
    files = sorted(glob.glob(os.path.join(path, "snapshots", "[0-9]*.h5")))
    if not files:
        raise OutputError(
            f"{path!r} holds no snapshots (expected {os.path.join(path, 'snapshots', '00000.h5')}; "
            f"a run writes them unless output.snapshot_every = 0)"
        )
    return files


def load_attrs(path):
    """A snapshot's or checkpoint's attributes only (its time, scene, config), without its arrays."""
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
    except FileNotFoundError:
        raise OutputError(f"{path!r} does not exist") from None
    except OSError as e:
        raise OutputError(f"{path!r} is not a readable tisph HDF5 file ({e})") from None


def write_xdmf(path, snapshots):
    """XDMF 3 temporal collection over the snapshot files, so ParaView and VisIt open the run.

    snapshots: list of (time, relative h5 path, number of particles, {dataset: (shape, dtype)}).
    """
    grids = []
    for t, rel, n, datasets in snapshots:

        def item(name):
            shape, dt = datasets[name]
            kind = "Float" if np.dtype(dt).kind == "f" else "Int"
            dims = " ".join(str(s) for s in shape)
            return (
                f'<DataItem Dimensions="{dims}" NumberType="{kind}" Precision="{np.dtype(dt).itemsize}" '
                f'Format="HDF">{rel}:/{name}</DataItem>'
            )

        attrs = []
        for name, (shape, dt) in datasets.items():
            if name == "position":
                continue
            atype = "Vector" if len(shape) == 2 and shape[1] == 3 else "Scalar"
            info = (
                f'        <Information Name="units" Value="{SNAPSHOT_UNITS[name]}"/>\n'
                if name in SNAPSHOT_UNITS
                else ""
            )
            attrs.append(
                f'      <Attribute Name="{name}" AttributeType="{atype}" Center="Node">\n{info}'
                f'        {item(name)}\n      </Attribute>'
            )
        grids.append(
            f'    <Grid Name="t{t:.6f}" GridType="Uniform">\n'
            f'      <Time Value="{t:.9g}"/>\n'
            f'      <Topology TopologyType="Polyvertex" NumberOfElements="{n}" NodesPerElement="1"/>\n'
            f'      <Geometry GeometryType="XYZ">\n        {item("position")}\n      </Geometry>\n'
            + "\n".join(attrs)
            + "\n    </Grid>"
        )
    text = (
        '<?xml version="1.0" ?>\n<Xdmf Version="3.0">\n  <Domain>\n'
        '  <Grid Name="particles" GridType="Collection" CollectionType="Temporal">\n'
        + "\n".join(grids)
        + "\n  </Grid>\n  </Domain>\n</Xdmf>\n"
    )
    write_text(path, text)


def clean_stale_parts(folder):
    """Remove temporary files a killed run left behind (never a complete file)."""
    if not os.path.isdir(folder):
        return
    for root, _, files in os.walk(folder):
        for f in files:
            if f.startswith(".") and ".part" in f:
                try:
                    os.unlink(os.path.join(root, f))
                except OSError:
                    pass
