"""``python -m zwidth``: the ``zwidth`` command line (see ``zwidth --help``)."""
from .cli import main

raise SystemExit(main())
