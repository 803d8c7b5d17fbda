"""``validate`` says which charted zones it read (a newcomer could not see that their ``[[zones]]`` were read)."""

from __future__ import annotations

from auvplan.cli import main

_TOML = """name = "zoned"
[bounds]
x = [0.0, 3000.0]
y = [0.0, 1000.0]
z = [-300.0, 0.0]
[terrain.synthetic]
kind = "plane"
depth = 200.0
cell_m = 100.0
[mission]
start = [100.0, 500.0, -150.0]
goal = [2900.0, 500.0, -150.0]
"""
_ZONES = [("wreck", 'point = [1000.0, 900.0]\nradius_m = 20.0\nabove_seabed_m = 15.0\n'),
          ("cable", 'line = [[1200.0, 0.0], [1300.0, 300.0]]\nbuffer_m = 10.0\ntop_m = 40.0\nbottom_m = 60.0\n'),
          ("lane", 'polygon = [[1500.0, 0.0], [1600.0, 0.0], [1600.0, 100.0]]\nbottom_m = 30.0\n'),
          ("park", 'polygon = [[2000.0, 0.0], [2100.0, 0.0], [2100.0, 100.0]]\n'),
          ("fifth", 'point = [2500.0, 900.0]\nradius_m = 20.0\n')]


def test_validate_names_the_zones_and_their_bands(tmp_path, capsys):
    """Oracle: the five zones by hand — the first four named with their bands, the fifth counted."""
    text = _TOML + "".join(f'[[zones]]\nname = "{n}"\n{body}' for n, body in _ZONES)
    (tmp_path / "s.toml").write_text(text, encoding="utf-8")
    assert main(["validate", str(tmp_path / "s.toml")]) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if "charted zone" in x]
    assert line == ("  5 charted zones kept out of: 'wreck' (15 m above the seabed); 'cable' (40 m to 60 m); "
                    "'lane' (the surface to 30 m); 'park' (the surface to the seabed); ... (1 more)")
    (tmp_path / "one.toml").write_text(_TOML + '[[zones]]\nname = "cable"\n' + _ZONES[1][1], encoding="utf-8")
    assert main(["validate", str(tmp_path / "one.toml")]) == 0
    assert "  1 charted zone kept out of: 'cable' (40 m to 60 m)\n" in capsys.readouterr().out
    (tmp_path / "none.toml").write_text(_TOML, encoding="utf-8")
    assert main(["validate", str(tmp_path / "none.toml")]) == 0
    assert "charted zone" not in capsys.readouterr().out
