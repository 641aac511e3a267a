"""The ``fricdamp`` command: one module per group of sub-commands.

* :mod:`fricdamp.cli.app` -- the parser, ``main``; ``run``, ``check``, ``demo``
* :mod:`fricdamp.cli.studies` -- ``sweep``, ``optimize``
* :mod:`fricdamp.cli.identify` -- ``identify``
* :mod:`fricdamp.cli.fit` -- ``fit``

Every name of :mod:`fricdamp.cli.app` is re-exported here (``fricdamp.cli:main`` is the
console script).
"""

from fricdamp.cli import app as _app

globals().update({_k: _v for _k, _v in vars(_app).items()
                  if not (_k.startswith("__") and _k.endswith("__"))})
del _app
