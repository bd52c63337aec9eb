"""``python -m aaria_pin.cli``: the same app as the ``aaria`` console script."""

from aaria_pin.cli import main

main()
