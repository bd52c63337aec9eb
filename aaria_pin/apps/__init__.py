"""Applications on the core and the Aaria layer: data sets, wrist, pick-place arm, torques."""
