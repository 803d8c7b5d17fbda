"""File access confined to the folders ``auvplan serve`` was started with.

A name the page sends is resolved against the served folders: ``..`` parts are refused outright,
an absolute path must lie inside a served folder, and the resolved path (every symbolic link
followed) must still lie inside one, so a link pointing out of a folder is refused too.
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path, PurePosixPath, PureWindowsPath

from ...errors import AuvplanError
from ...io.scenario.specs import Scenario, named_files

__all__ = ["PathRefused", "Roots"]


class PathRefused(AuvplanError):
    """A path the page asked for that lies outside the served folders."""


def _utf8(text: str) -> bool:
    """Whether ``text`` is UTF-8 text (a lone surrogate is not)."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


@dataclass(frozen=True)
class Roots:
    """The folders the server may read and write in.

    Parameters
    ----------
    folders : tuple of pathlib.Path
        Absolute, resolved folders; the first is where saved results go.
    """

    folders: tuple[Path, ...]

    @classmethod
    def of(cls, folders: Sequence[str | Path]) -> Roots:
        """Serve ``folders`` (resolved now, so a later change of directory does not move them).

        Parameters
        ----------
        folders : sequence of str or pathlib.Path
            Existing folders.

        Returns
        -------
        Roots
            The confinement.
        """
        return cls(tuple(Path(f).resolve() for f in folders))

    def inside(self, path: Path) -> bool:
        """Whether ``path`` (resolved, links followed) lies in a served folder.

        Parameters
        ----------
        path : pathlib.Path
            Any path.

        Returns
        -------
        bool
            True inside one of the folders.
        """
        real = path.resolve()
        return any(real == r or real.is_relative_to(r) for r in self.folders)

    def confine(self, sc: Scenario) -> None:
        """Refuse a scenario that names a data file outside the served folders (and the package's own data).

        Relative names resolve against the scenario's folder, links are followed: a currents or tide file
        by relative path (``../../elsewhere/c.nc``) is refused before it is read.  The files the loader itself
        reads (a ``[survey]`` area, to derive the bounds) are refused before it, by :meth:`confine_text`.

        Parameters
        ----------
        sc : Scenario
            The scenario about to be built.
        """
        for key, name in named_files(sc):
            self._confine_one(sc.source, sc.base_dir, key, name)

    def confine_text(self, text: str, source: str, base_dir: Path | None) -> None:
        """Refuse scenario text naming, outside the served folders, a file the scenario loader reads itself.

        The loader reads a ``[survey] file`` or ``centerline_file`` to derive the bounds of a scenario given in
        degrees (:func:`auvplan.io.scenario.inputs.geoinput.resolve_positions`): call this before it, then
        :meth:`confine` on the scenario it returns (the other files, read when the world is built).  Text that
        is not TOML is left to the loader's own message.

        Parameters
        ----------
        text : str
            The scenario's TOML.
        source : str
            Its name, for messages.
        base_dir : pathlib.Path or None
            The folder relative names resolve against.
        """
        try:
            doc = tomllib.loads(text)
        except (tomllib.TOMLDecodeError, RecursionError):
            return
        survey = doc.get("survey")
        if isinstance(survey, dict):
            for key in ("file", "centerline_file"):
                name = survey.get(key)
                if isinstance(name, str) and name:
                    self._confine_one(source, base_dir, f"[survey] {key}", name)

    def _confine_one(self, source: str, base_dir: Path | str | None, key: str, name: str) -> None:
        data = Path(str(resources.files("auvplan") / "data")).resolve()  # as the readers find it (auvplan.data is
        # a namespace package: its files() is a MultiplexedPath, whose str is no path)
        p = Path(name)
        if not p.is_absolute() and base_dir is not None:
            p = Path(base_dir) / p
        real = p.resolve()
        if not (self.inside(real) or real == data or real.is_relative_to(data)):
            raise PathRefused(f"{source}: {key} = {name!r}: outside the served folders "
                              f"({', '.join(map(str, self.folders))}); serve its folder too (--root)")

    def resolve(self, name: str, must_exist: bool = True) -> Path:
        """The path of ``name`` inside the served folders, or :class:`PathRefused`.

        Parameters
        ----------
        name : str
            Relative to the first folder holding it, or absolute inside a folder.
        must_exist : bool, optional
            Refuse a name that does not exist in any folder.

        Returns
        -------
        pathlib.Path
            The resolved path.

        Raises
        ------
        PathRefused
            For ``..`` parts, a path outside the folders (also through a link) or a missing file.
        """
        if not isinstance(name, str) or not name.strip() or "\x00" in name or len(name) > 4096 \
                or not name.isprintable() or not _utf8(name):
            # a lone surrogate (JSON's "\ud800") was 'UnicodeEncodeError: … surrogates not allowed' (hostile round 22)
            raise PathRefused(f"{str(name)[:80]!r}: not a file name")
        if ".." in PurePosixPath(name).parts or ".." in PureWindowsPath(name).parts:
            raise PathRefused(f"{name}: '..' is not allowed; name a file inside the served folders "
                              f"({', '.join(map(str, self.folders))})")
        p = Path(name)
        candidates = [p] if p.is_absolute() else [r / p for r in self.folders]
        for c in candidates:
            if not self.inside(c):
                continue
            if c.exists() or not must_exist:
                return c.resolve()
        if p.is_absolute() or any(c.exists() or c.is_symlink() for c in candidates):
            raise PathRefused(f"{name}: outside the served folders ({', '.join(map(str, self.folders))})")
        raise PathRefused(f"{name}: no such file in the served folders ({', '.join(map(str, self.folders))})")
