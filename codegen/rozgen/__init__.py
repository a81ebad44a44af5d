# SPDX-License-Identifier: Apache-2.0
"""rozgen: turn robot.toml manifests into static C tables for roz.

Pipeline, one module per step:

- ``load``:      read the file, check UTF-8, parse TOML (tomllib).
- ``validate``:  apply the rules (listed in ``rozgen.validate``) and build the
                 immutable model of ``rozgen.model``.
- ``canonical``: the canonical JSON text of a model (``rozgen --json``).
- ``render``:    jinja2 templates in ``rozgen/templates`` -> C sources.
- ``cli``:       the ``rozgen`` command.

Validation never emits, and emission never validates: the renderers only
ever see a model that passed every rule.
"""

__version__ = "0.1.0"
