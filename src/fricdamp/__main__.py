"""``python -m fricdamp``: the ``fricdamp`` command (:func:`fricdamp.cli.main`)."""

import sys

from fricdamp.cli import main

if __name__ == "__main__":
    sys.exit(main())
