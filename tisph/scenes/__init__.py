"""One module per scene, each runnable as python -m tisph.scenes.NAME."""
