"""Figures without a display, saved whole or not at all (atomic rename)."""
from ..io import atomic_path


def pyplot():
    """matplotlib.pyplot on the Agg backend (no window, no display needed)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save(fig, path, dpi=110, tight=True):
    """Lay out, write to a temporary name and rename, close."""
    import matplotlib.pyplot as plt
    if tight:
        fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight", pad_inches=0.08)   # titles never clipped
    plt.close(fig)
