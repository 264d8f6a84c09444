"""`python -m tisph.view RUN`: the viewer (tisph/viz/view.py), under the name the README gives."""
import sys

from .viz.view import main

if __name__ == "__main__":
    sys.exit(main())
