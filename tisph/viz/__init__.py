"""Pictures: the off-screen renderer (render.py) and its colours (colours.py), and the live window
(live.py); tisph/view.py renders a run again from its snapshots with them."""
