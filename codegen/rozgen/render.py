# SPDX-License-Identifier: Apache-2.0
"""C sources from validated manifests, through the jinja2 templates.

Output is a pure function of the model, the rozgen version and the source
labels (repository-relative paths and sha256 of the input bytes): no time,
no host, no absolute path. All text is ASCII with ``\\n`` line ends.
"""

from dataclasses import dataclass

import jinja2

from rozgen import __version__, identity, names
from rozgen.fmt import c_comment, c_double, c_string
from rozgen.model import Manifest


@dataclass(frozen=True)
class Source:
    """Where a manifest came from, as the banner names it."""

    label: str  # repository-relative path, "/"-separated, never absolute
    sha256: str  # hex digest of the file bytes


REGISTRY_FILE = "roz_builtin_registry.c"


def robot_files(manifest: Manifest) -> tuple[str, str, str]:
    """Names of the C files generated for one robot."""
    rid = manifest.robot_id
    return f"{rid}_channels.h", f"{rid}_manifest.h", f"{rid}_manifest.c"


def rust_file(manifest: Manifest) -> str:
    """Name of the Rust module generated for one robot (docs/rust.md)."""
    return f"{manifest.robot_id}_channels.rs"


def render_robot(manifest: Manifest, source: Source) -> dict[str, str]:
    """File name -> content of the four files of one robot: three C, one Rust."""
    env = _environment()
    channels_h, manifest_h, manifest_c = robot_files(manifest)
    channels_rs = rust_file(manifest)
    cmd_macros = [names.command_constant(manifest.robot_id, c.name) for c in manifest.commands]
    state_macros = [names.state_constant(manifest.robot_id, c.name) for c in manifest.states]
    input_macros = [names.input_constant(manifest.robot_id, c.name) for c in manifest.inputs]
    count_macros = [manifest.prefix + s for s in ("_N_COMMANDS", "_N_STATES", "_CONTROL_RATE_HZ",
                                                  "_ROBOT_ID", "_INTERFACE_HASH")]
    if manifest.inputs:
        count_macros.append(manifest.prefix + "_N_INPUTS")
    n_max = max(len(manifest.commands), len(manifest.states) + len(manifest.inputs))
    context = {
        "m": manifest,
        "sources": [source],
        "channels_h": channels_h,
        "channels_rs": channels_rs,
        "manifest_h": manifest_h,
        "cmd_macros": cmd_macros,
        "state_macros": state_macros,
        "input_macros": input_macros,
        # Column widths, so that values and comments line up.
        "width": max(map(len, cmd_macros + state_macros + input_macros + count_macros)),
        "index_width": len(str(n_max - 1)),
        "interface_hash": "0x%016x" % identity.interface_hash(manifest),
        "section": identity.SECTION,
        "record_version": identity.RECORD_VERSION,
        "identity_record": list(identity.record(manifest)),
    }
    return {
        channels_h: env.get_template("channels.h.j2").render(context),
        manifest_h: env.get_template("manifest.h.j2").render(context),
        manifest_c: env.get_template("manifest.c.j2").render(context),
        channels_rs: env.get_template("channels.rs.j2").render(context),
    }


def render_registry(robots: list[tuple[Manifest, Source]]) -> str:
    """roz_builtin_registry.c over ``robots`` (any order; sorted by id here)."""
    ordered = sorted(robots, key=lambda pair: pair[0].robot_id)
    context = {
        "manifests": [m for m, _ in ordered],
        "headers": [robot_files(m)[1] for m, _ in ordered],
        "sources": [s for _, s in ordered],
    }
    return _environment().get_template("registry.c.j2").render(context)


def _environment() -> jinja2.Environment:
    env = jinja2.Environment(
        loader=jinja2.PackageLoader("rozgen", "templates"),
        undefined=jinja2.StrictUndefined,
        keep_trailing_newline=True,
        autoescape=False,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters["c_string"] = c_string
    env.filters["c_double"] = c_double
    env.filters["c_comment"] = c_comment
    env.globals["version"] = __version__
    return env
