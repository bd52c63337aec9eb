"""The Aaria layer: extended DH tables, presets, oscillation tables, random structures, ``senSen``.

It builds core robot descriptions from DH tables and adds the paper's 91-column ``senSen`` view
of the core run record.
"""
