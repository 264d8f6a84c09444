"""The peers' benches: PySPH's and DualSPHysics' dam break and flume beside tisph's, each code at
its own recommended settings. They install PySPH into a virtual environment and build
DualSPHysics from its source, so the wheel leaves this package out; a clone of tisph's source
(pip install -e .) has it, and python -m tisph.bench --speed --peer, --waves run it."""
