"""How auvplan's code runs: compiled kernels and independent tasks.

- :mod:`auvplan.runtime.jit`: the ``@kernel`` decorator (numba, cached on disk and keyed on the text
  of every kernel module) and the switch that runs the same kernels as plain Python.
- :mod:`auvplan.runtime.parallel`: the one mapper of independent tasks (:class:`~auvplan.runtime.parallel.Runner`):
  in this process, on local dask workers or on a scheduler, with retries and resume.

Nothing is imported here: a caller names the module it uses, so importing a kernel does not bring in dask.
"""

__all__: list[str] = []
