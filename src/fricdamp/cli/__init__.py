"""The ``fricdamp`` command: one module per sub-command.

* :mod:`fricdamp.cli.app` -- the parser and ``main``
* :mod:`fricdamp.cli.run` -- ``run``
* :mod:`fricdamp.cli.check` -- ``check``
* :mod:`fricdamp.cli.demo` -- ``demo``
* :mod:`fricdamp.cli.sweep` -- ``sweep``
* :mod:`fricdamp.cli.optimize` -- ``optimize``
* :mod:`fricdamp.cli.identify` -- ``identify``
* :mod:`fricdamp.cli.fit` -- ``fit``
* :mod:`fricdamp.cli._common` -- what they share (exit codes, output, the verdict line);
  :mod:`fricdamp.cli._studies` -- what ``sweep`` and ``optimize`` share;
  :mod:`fricdamp.cli.studies` re-exports both study commands (their module before the split)

Every name of :mod:`fricdamp.cli.app` is re-exported here (``fricdamp.cli:main`` is the
console script).
"""

from fricdamp.cli import app as _app

globals().update({_k: _v for _k, _v in vars(_app).items()
                  if not (_k.startswith("__") and _k.endswith("__"))})
del _app
