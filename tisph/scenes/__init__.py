"""The scenes: one module or package a scene, each runnable as `python -m tisph.scenes.NAME` and
registered once in tisph/registry.py (where the contract a scene keeps is written)."""
