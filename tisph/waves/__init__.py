"""Wave making: linear theory (theory.py) at the bottom, the paddle's motion (motion.py), irregular
seas (irregular.py), the second-order stroke (second_order.py), active absorption (absorb.py),
and the [paddle] table that puts them together (paddle.py). Nothing here imports back up."""
