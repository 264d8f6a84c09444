"""tisph: weakly-compressible SPH for free-surface water and sediment, on Taichi."""

import os as _os

# Taichi prints a banner on import; run.log records the version instead.
_os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")

__version__ = "0.1.0"


def __getattr__(name):
    """tisph.Case and tisph.run (tisph/api.py), imported when first used: `import tisph` stays light."""
    if name in ("Case", "run", "Result"):
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'tisph' has no attribute {name!r}")
