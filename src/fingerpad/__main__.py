"""``python -m fingerpad``: the command line, as the ``fingerpad`` script runs it."""

from .cli import main

if __name__ == "__main__":
    main()
