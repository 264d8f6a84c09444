"""Physics modules: each term of the papers' equations as one Module (tisph/hooks/module.py),
built on the small pure functions of tisph/terms/."""
