"""What the engine and its modules agree on, below both: the Module interface and its MatParam
declarations (module.py; Param, a config Key, and the runtime parameters a config key sets are
in tisph/settings, read without Taichi), and the health codes a step reports (health.py)."""
