"""``python -m fricdamp.cli``: the ``fricdamp`` command."""

import sys

from fricdamp.cli.app import main

if __name__ == "__main__":
    sys.exit(main())
