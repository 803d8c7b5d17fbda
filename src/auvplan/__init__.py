"""auvplan — plan, check and simulate 3D missions for autonomous underwater vehicles.

Layers (each imports only from those below; checked by import-linter):
``cli`` → ``bench | io | viz`` → ``sim`` → ``planners | guidance | vehicles`` →
``cost | metrics`` → ``world | path | optim`` → ``errors | geometry | _types``.
"""

__version__ = "0.1.0"

__all__ = ["__version__"]
