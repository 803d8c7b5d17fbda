"""The scenario text a results folder keeps (``scenario.toml``) with what the build derived written into it
(issue 51): the ``[origin]`` derived from a mission written in degrees and the ``[bounds]`` x/y derived from
the mission's extent and clipped to the data, so the folder's exports, its ``report``/``export`` and
``mission check`` all use the datum and the operating region the run used — even if the derivation rules
change later.  The user's own text is kept as it is (comments and all); the derived tables are added at the
end, or the x/y lines under an existing ``[bounds]`` header that gave only z.
"""

from __future__ import annotations

import re
import tomllib

from ...world import World

__all__ = ["with_derived_frame"]


def with_derived_frame(text: str, world: World) -> str:
    """The scenario text with the world's origin and x/y bounds written in where the text had none.

    Parameters
    ----------
    text : str
        The scenario's TOML text (empty: nothing to add to).
    world : World
        The world built from it.

    Returns
    -------
    str
        The text, with ``[origin]`` lat/lon and ``[bounds]`` x/y (full precision) added where derived.
    """
    if not text:
        return text
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        return text
    b = world.bounds
    xy = f"x = [{b.xmin!r}, {b.xmax!r}]\ny = [{b.ymin!r}, {b.ymax!r}]\n"
    note = "# derived by auvplan when the run was made (issue 51)\n"
    out = text if text.endswith("\n") else text + "\n"
    bounds = data.get("bounds")
    if not (isinstance(bounds, dict) and ("x" in bounds or "y" in bounds)):
        header = re.search(r"^[ \t]*\[bounds\][ \t]*(#[^\n]*)?\n", out, re.M)
        if bounds is None:
            out += f"\n[bounds]  {note}{xy}"
        elif header is not None:
            out = out[:header.end()] + note + xy + out[header.end():]
    if world.origin is not None and "origin" not in data:
        out += f"\n[origin]  {note}lat = {world.origin[0]!r}\nlon = {world.origin[1]!r}\n"
    return out
