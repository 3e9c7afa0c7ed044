"""``python -m tumble``: the command line, as the ``tumble`` command runs it."""

from tumble.cli import main

if __name__ == "__main__":
    main()
