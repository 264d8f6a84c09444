"""tisph: weakly-compressible SPH for free-surface water and sediment, on Taichi."""
import os as _os

# Taichi prints a banner on import; run.log records the version instead.
_os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")

__version__ = "0.1.0"
