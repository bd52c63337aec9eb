"""Files: run files (``.h5``, ``.mat``), data sets and their readers, tables, atomic outputs.

Above the core (it stores the core's run record), below the Aaria layer (it knows no DH table).
"""
