"""``python -m fricdamp``: the ``fricdamp`` command (:func:`fricdamp.cli.app.main`)."""

import sys

from fricdamp.cli.app import main

if __name__ == "__main__":
    sys.exit(main())
