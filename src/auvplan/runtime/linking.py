"""Every kernel runs its own machine code: its calls to other kernels are bound inside it, whatever was loaded before.

A result's last bits depended on whether numba compiled the kernels in this process or loaded them from its
disk cache (and, in a process that loaded them, on which kernel ran first).
numba links a kernel's callees into the caller's LLVM module as ``linkonce_odr`` copies (numba's
``CPUCodeLibrary._get_module_for_linking``: "to allow for multiple definitions, inlining, and removal of unused
exports"), then optimises the caller's module once more.  A callee LLVM does not inline stays a *call* to a
weak symbol, and at run time the JIT linker binds that call to the first definition of the name it has: the
callee's own compiled code when that was loaded before the caller, the caller's copy otherwise.  The two
copies are the same function optimised twice, and under ``fastmath={"contract"}`` the second optimisation may
fuse the other product of a sum into the multiply-add (``(1 - v) z[i, k] + v z[i, k + 1]`` in the seabed's
``_segment``: the copy inside ``cell_extremes`` fuses ``v z[i, k + 1]``, ``_segment``'s own code
``(1 - v) z[i, k]``), so the result's last bits depended on which was loaded first.  A process that compiles
compiles every callee before its caller and so calls the callees' own code; a process that loads the caller
from numba's disk cache (numba loads no callee for it) calls the caller's copies: ``cell_extremes`` on the
salish-shelf grid differed, and the simulated altitude through the terrain's coefficients by up to 5.7e-14 m.

Here every ``@kernel`` is compiled by :class:`OwnCodeCompiler`, whose code library (:class:`OwnCodeLibrary`)
gives every function linked into the kernel's module *internal* linkage once LLVM has optimised it: each call
is bound inside the caller's own object, in this process and in every process that loads it from the cache,
whatever was loaded before.  The optimised code is the one numba made before (the linkage is changed after
the optimisation), so the results are those a process loading today's cache computed.  Cost: a pass over the
module's function list at each compile (microseconds), nothing at load.
"""

from __future__ import annotations

from typing import Any

import llvmlite.binding as ll  # type: ignore[import-untyped]
from numba.core.codegen import JITCodeLibrary
from numba.core.compiler import Compiler

__all__ = ["OwnCodeCompiler", "OwnCodeLibrary", "bind_locally"]

_SHARED = frozenset({ll.Linkage.linkonce_odr, ll.Linkage.linkonce_any, ll.Linkage.weak_odr, ll.Linkage.weak_any})
"""Linkages the JIT linker may bind to another object's definition of the same name."""


def bind_locally(module: Any) -> int:
    """Give every function ``module`` defines with a weak or link-once linkage internal linkage.

    Parameters
    ----------
    module : llvmlite.binding.ModuleRef
        An optimised LLVM module about to be compiled.

    Returns
    -------
    int
        How many functions were changed.
    """
    changed = 0
    for fn in module.functions:
        if not fn.is_declaration and fn.linkage in _SHARED:
            fn.linkage = ll.Linkage.internal
            changed += 1
    return changed


class OwnCodeLibrary(JITCodeLibrary):
    """The JIT code library of numba whose module, once optimised, calls only its own copies of other functions."""

    def _optimize_final_module(self) -> None:
        super()._optimize_final_module()  # type: ignore[no-untyped-call]  # numba is untyped
        bind_locally(self._final_module)


class OwnCodeCompiler(Compiler):
    """The default compiler of numba (its ``pipeline_class``) lowering into an :class:`OwnCodeLibrary`."""

    def compile_extra(self, func: Any) -> Any:
        """Compile ``func`` as numba's ``Compiler.compile_extra``, into an :class:`OwnCodeLibrary`.

        Parameters
        ----------
        func : callable
            The Python function of the kernel.

        Returns
        -------
        numba.core.compiler.CompileResult
            numba's result; its library is an :class:`OwnCodeLibrary` unless a library was given or the
            target's codegen makes another kind of library (then numba's own, unchanged).
        """
        codegen = self.state.targetctx.codegen()
        if self.state.library is None and getattr(codegen, "_library_class", None) is JITCodeLibrary:
            # numba's NativeLowering makes a JITCodeLibrary just so when none is given
            library = OwnCodeLibrary(codegen, func.__qualname__)  # type: ignore[no-untyped-call]
            library.enable_object_caching()  # type: ignore[no-untyped-call]
            self.state.library = library
        return super().compile_extra(func)  # type: ignore[no-untyped-call]
