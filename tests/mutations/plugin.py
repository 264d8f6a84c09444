"""The pytest plugin that applies TISPH_MUTATION before the tests import tisph's physics."""
import os

from . import apply

if os.environ.get("TISPH_MUTATION"):
    apply(os.environ["TISPH_MUTATION"])
