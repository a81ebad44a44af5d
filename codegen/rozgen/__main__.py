# SPDX-License-Identifier: Apache-2.0
"""``python -m rozgen``: same as the ``rozgen`` console script."""

from rozgen.cli import main

raise SystemExit(main())
