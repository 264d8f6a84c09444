"""A case's settings: the key type (schema), the keys every scene shares (shared_keys), the
numerics schemes, the shared material tables, reading and checking a case file (config), the
resolved case read by attribute (resolved), the compile-time physics switches (switches) and the
plausibility checks run before anything compiles (plausible)."""
