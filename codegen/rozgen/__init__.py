# SPDX-License-Identifier: Apache-2.0
"""rozgen: turn robot.toml manifests into static C tables for roz.

Pipeline, one module per step:

- ``load``:      read the file's bytes.
- ``validate``:  apply the rules -- roz's C implementation of them, run by
                 ``rozgen.checker`` -- and build the immutable model of
                 ``rozgen.model``.
- ``render``:    jinja2 templates in ``rozgen/templates`` -> C sources.
- ``cli``:       the ``rozgen`` command.

Validation never emits, and emission never validates: the renderers only
ever see a model that passed every rule.
"""

__version__ = "0.1.0"
