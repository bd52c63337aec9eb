"""Run the ``aaria`` command line from a checkout: ``python cli.py --help``."""

from aaria_pin.cli import main

if __name__ == "__main__":
    main()
