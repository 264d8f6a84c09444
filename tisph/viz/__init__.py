"""Pictures: the off-screen renderer (render.py) and its colours (colours.py), the live window
(live.py), and the viewer that renders a run again from its snapshots (view.py)."""
