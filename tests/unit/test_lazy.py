"""The packages' names loaded on first access (auvplan.runtime.lazy): loaded from their module, kept, listed."""

import importlib
import subprocess
import sys

import pytest


@pytest.mark.parametrize("package", ["auvplan", "auvplan.nav", "auvplan.sim", "auvplan.planners", "auvplan.endurance",
                                     "auvplan.survey"])
def test_every_exported_name_resolves_to_its_defining_module_and_unknown_names_are_named(package):
    mod = importlib.import_module(package)
    for name in mod.__all__:
        assert getattr(mod, name) is not None
        assert name in dir(mod)
    with pytest.raises(AttributeError, match=rf"module '{package}' has no attribute 'no_such_name'"):
        mod.no_such_name  # noqa: B018


def test_a_name_is_loaded_on_first_access_only_and_kept():
    code = ("import sys, auvplan.sim as s; assert 'auvplan.sim.loop' not in sys.modules; "
            "f = s.simulate; assert 'auvplan.sim.loop' in sys.modules; "
            "assert s.__dict__['simulate'] is f is sys.modules['auvplan.sim.loop'].simulate; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"


def test_a_name_its_submodule_shadows_is_the_name_after_any_first_access():
    """``auvplan.endurance.assess`` is a function of the submodule ``assess``: importing that submodule for
    another name (``Endurance``) binds the package's ``assess`` to the module, which the lazy loader puts back."""
    code = ("import types, auvplan.endurance as e; from auvplan.endurance import Endurance; "
            "from auvplan.endurance import assess; assert not isinstance(assess, types.ModuleType); "
            "assert assess is e.assess is __import__('sys').modules['auvplan.endurance.assess'].assess; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "ok"


def test_lazy_attributes_of_a_fresh_package_load_keep_list_and_refuse(monkeypatch):
    """On a package made here (the installed packages' hooks were made at their import, before any test):
    a listed name is the defining module's object, kept in the namespace; ``dir`` lists the exported names
    before they are loaded; a name not listed raises AttributeError naming the package (mutants21)."""
    import json
    import math
    import types

    from auvplan.runtime.lazy import lazy_attributes

    pkg = types.ModuleType("auvplan_lazy_probe")
    monkeypatch.setitem(sys.modules, pkg.__name__, pkg)
    getattr_, dir_ = lazy_attributes(pkg.__name__, {"sqrt": "math", "dumps": "json"}, ["sqrt", "dumps"])
    assert {"sqrt", "dumps"} <= set(dir_()) and "sqrt" not in vars(pkg)
    assert getattr_("sqrt") is math.sqrt and vars(pkg)["sqrt"] is math.sqrt and "dumps" not in vars(pkg)
    assert getattr_("dumps") is json.dumps
    with pytest.raises(AttributeError, match=r"^module 'auvplan_lazy_probe' has no attribute 'loads'$"):
        getattr_("loads")  # defined by json, but not listed
