"""What the engine and its modules agree on, below both: the Module interface and its Param and
MatParam declarations (module.py), the runtime parameters a config key sets (keys.py, read by
tisph.config without Taichi), and the health codes a step reports (health.py)."""
