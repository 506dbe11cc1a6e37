# SPDX-FileCopyrightText: 2026 The zwidth authors
# SPDX-License-Identifier: Apache-2.0

"""``python -m zwidth``: the ``zwidth`` command line (see ``zwidth --help``)."""
from .cli import main

raise SystemExit(main())
