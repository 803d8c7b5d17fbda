"""The population planners of document 002 (IABC, ABC, GA, PSO, DE) and their pipelines."""

__all__: list[str] = []
