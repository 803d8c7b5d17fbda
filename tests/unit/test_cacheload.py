"""The guard of the deferred cache load (``runtime.cacheload``, issue 56): which cached kernels may be loaded
without numba's registries (nopython code, nothing lifted or re-initialised, every declared symbol resolvable
now), the switch and the numba versions, and the load itself on stand-ins: NRT first, numba's full refresh
for anything not deferrable, nothing on a miss.  (A real warm process: ``tests/integration/test_cacheload_warm.py``.)"""

from __future__ import annotations

import ctypes
import types

import pytest

pytest.importorskip("numba")
ll = pytest.importorskip("llvmlite.binding")
from llvmlite import ir  # noqa: E402

from auvplan.runtime import cacheload  # noqa: E402

_KEEP = ctypes.c_double(1.0)  # the address a known symbol points at, alive for the module's life
ll.add_symbol("auvplan_test_known_symbol", ctypes.addressof(_KEEP))


def _module(declared: list[str]):  # noqa: ANN202
    """An LLVM module defining ``caller``, which calls every function named in ``declared`` (declared only)."""
    module = ir.Module(name="t")
    fnty = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()])
    caller = ir.Function(module, fnty, name="caller")
    builder = ir.IRBuilder(caller.append_basic_block())
    value = caller.args[0]
    for name in declared:
        value = builder.call(ir.Function(module, fnty, name=name), [value])
    builder.ret(value)
    return ll.parse_assembly(str(module))


def _bitcode(declared: list[str]) -> bytes:
    return bytes(_module(declared).as_bitcode())


def _object(declared: list[str]) -> bytes:
    """The module's machine code as this platform's object file (ELF on Linux), as numba caches it."""
    ll.initialize_native_target()  # as numba's code generator does
    ll.initialize_native_asmprinter()
    machine = ll.Target.from_default_triple().create_target_machine(codemodel="jitdefault")
    return bytes(machine.emit_object(_module(declared)))


def _payload(declared: list[str], objectmode: bool = False, lifted: tuple = (), reload_init: tuple = (),
             kind: str = "object", elf: bool = True) -> tuple:
    obj = _object(declared) if elf else b"not an object file numba wrote"
    libdata = ("lib", kind, (obj, _bitcode(declared)))
    return (libdata, None, None, None, objectmode, list(lifted), "", list(reload_init), ())


def _context(defined: set[str] | None = None) -> types.SimpleNamespace:
    engine = types.SimpleNamespace(_defined_symbols=defined or set())
    ctx = types.SimpleNamespace(refreshes=0, codegen=lambda: types.SimpleNamespace(_engine=engine))

    def refresh() -> None:
        ctx.refreshes += 1

    ctx.refresh = refresh
    return ctx


@pytest.mark.parametrize("elf", [True, False], ids=["object-file", "bitcode"])
def test_a_kernel_is_deferrable_only_when_every_symbol_it_needs_resolves_now(elf):
    """Read from the object file's symbol table (ELF), else from the bitcode's declarations."""
    if elf and cacheload._elf_undefined(_object([])) is None:
        pytest.skip("this platform's object files are not ELF: the bitcode is read")
    ctx = _context(defined={"in_numba_s_engine"})
    assert cacheload.deferrable(_payload([], elf=elf), ctx)
    assert cacheload.deferrable(_payload(["auvplan_test_known_symbol", "in_numba_s_engine"], elf=elf), ctx)
    # a symbol only a registry would add (numba's hash secret is one): numba's full refresh first
    assert not cacheload.deferrable(_payload(["auvplan_test_known_symbol", "auvplan_test_unknown_symbol"], elf=elf),
                                    ctx)


def test_the_symbols_read_from_the_object_file_and_from_the_bitcode():
    names = ["auvplan_test_unknown_symbol", "auvplan_test_known_symbol"]
    assert sorted(cacheload._declared_symbols(_bitcode(names))) == sorted(names)
    undefined = cacheload._elf_undefined(_object(names))
    if undefined is not None:
        assert sorted(undefined) == sorted(names)
    assert cacheload._elf_undefined(b"\x7fELF\x01\x01 a 32-bit one") is None
    cut = (("lib", "object", (b"\x7fELF\x02\x01 cut short", b"")), None, None, None, False, [], "", [], ())
    assert not cacheload.deferrable(cut, _context())  # not an object file numba wrote: numba's own load


@pytest.mark.parametrize("change", [dict(objectmode=True), dict(lifted=("loop",)), dict(reload_init=(print,)),
                                    dict(kind="bitcode")])
def test_objmode_lifted_loops_parfors_and_other_serialisations_are_never_deferred(change):
    assert not cacheload.deferrable(_payload([], **change), _context())
    assert not cacheload.deferrable(("not", "numba's", "layout"), _context())


def test_the_switch_and_the_numba_versions(monkeypatch):
    import numba

    monkeypatch.delenv(cacheload.ENV_VAR, raising=False)
    for version, on in (("0.68.0", True), ("0.68.1", True), ("0.67.1", False), ("0.69.0", False), ("1.0.0", False),
                        ("0.68.dev0", True), ("x.y", False)):
        monkeypatch.setattr(numba, "__version__", version)
        assert cacheload.enabled() is on, version
    monkeypatch.setattr(numba, "__version__", "0.68.1")
    for value, on in (("1", False), ("yes", False), ("0", True), ("", True)):
        monkeypatch.setenv(cacheload.ENV_VAR, value)
        assert cacheload.enabled() is on, value


class _Cache:
    """numba's ``Cache`` as :func:`cacheload.load_overload` reads it, its file holding ``payload``."""

    def __init__(self, payload: tuple | None, log: list[str]) -> None:
        self._enabled = True
        self._cache_file = types.SimpleNamespace(load=lambda key: log.append(f"load {key}") or payload)
        self._impl = types.SimpleNamespace(rebuild=lambda ctx, data: log.append("rebuild") or ("cres", data))
        self._guard_against_spurious_io_errors = lambda: __import__("contextlib").nullcontext()

    def _index_key(self, sig, codegen):  # noqa: ANN001, ANN202, ARG002
        return sig


@pytest.mark.parametrize("declared, refreshes", [([], 0), (["auvplan_test_unknown_symbol"], 1), (None, 0)])
def test_the_load_starts_numba_s_runtime_and_refreshes_only_what_is_not_deferrable(monkeypatch, declared,
                                                                                   refreshes):
    from numba.core.runtime import nrt

    log: list[str] = []
    monkeypatch.setattr(nrt.rtsys, "initialize", lambda ctx: log.append("nrt"))
    monkeypatch.setattr(cacheload, "STATS", {"deferred": 0, "refreshed": 0})
    ctx = _context()
    payload = None if declared is None else _payload(declared)
    got = cacheload.load_overload(_Cache(payload, log), "sig", ctx)
    assert ctx.refreshes == refreshes
    if payload is None:  # a miss: numba compiles (and its compiler refreshes both contexts)
        assert got is None and log == ["nrt", "load sig"] and cacheload.STATS == {"deferred": 0, "refreshed": 0}
    else:
        assert got == ("cres", payload) and log == ["nrt", "load sig", "rebuild"]
        assert cacheload.STATS == {"deferred": 1 - refreshes, "refreshed": refreshes}


def test_loads_after_the_registries_are_in_take_numba_s_own_path(monkeypatch):
    from numba.core.imputils import builtin_registry

    monkeypatch.delenv(cacheload.ENV_VAR, raising=False)
    monkeypatch.setattr(cacheload, "enabled", lambda: True)
    assert cacheload.use_deferred(types.SimpleNamespace(_registries={}))
    assert not cacheload.use_deferred(types.SimpleNamespace(_registries={builtin_registry: object()}))
    monkeypatch.setattr(cacheload, "enabled", lambda: False)
    assert not cacheload.use_deferred(types.SimpleNamespace(_registries={}))


def test_the_tested_range_takes_both_its_ends(monkeypatch):
    """TESTED is a range, first and last inclusive (one version today: a wider range keeps its first end;
    mutants21: the first end read as the last was not seen with both ends equal)."""
    import numba

    monkeypatch.delenv(cacheload.ENV_VAR, raising=False)
    monkeypatch.setattr(cacheload, "TESTED", ((0, 66), (0, 68)))
    for version, on in (("0.65.1", False), ("0.66.0", True), ("0.67.2", True), ("0.68.1", True), ("0.69.0", False)):
        monkeypatch.setattr(numba, "__version__", version)
        assert cacheload.enabled() is on, version


def test_auvplan_s_kernel_cache_defers_exactly_when_use_deferred_says(monkeypatch):
    """The hook in ``jit.KernelCache.load_overload``: :func:`cacheload.load_overload` when
    :func:`cacheload.use_deferred` (the switch, the versions, no registries yet), numba's own load otherwise
    (after a compile, or with ``AUVPLAN_NUMBA_REFRESH=1``).  No mutation site: planted by hand (mutants21)."""
    from numba.core import caching

    from auvplan.runtime import jit

    def probe(x):  # noqa: ANN001, ANN202
        return x

    cache = jit._cache_class(jit._package_root(probe))(probe)
    calls: list[str] = []
    monkeypatch.setattr(cacheload, "load_overload", lambda c, sig, ctx: calls.append("auvplan") or "a")
    monkeypatch.setattr(caching.Cache, "load_overload", lambda self, sig, ctx: calls.append("numba") or "n")
    for deferred, path in ((True, "auvplan"), (False, "numba")):
        monkeypatch.setattr(cacheload, "use_deferred", lambda ctx, d=deferred: d)
        assert cache.load_overload("sig", object()) == path[0] and calls[-1] == path
    monkeypatch.undo()
    monkeypatch.setenv(cacheload.ENV_VAR, "1")  # the switch, through use_deferred itself
    monkeypatch.setattr(cacheload, "load_overload", lambda c, sig, ctx: calls.append("auvplan") or "a")
    monkeypatch.setattr(caching.Cache, "load_overload", lambda self, sig, ctx: calls.append("numba") or "n")
    assert cache.load_overload("sig", types.SimpleNamespace(_registries={})) == "n"
