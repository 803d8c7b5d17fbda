"""Shared fixtures: the real built-in worlds (built once per session) and small synthetic scenes."""

from __future__ import annotations

import pytest

from auvplan.io.scenario import loader as sc


@pytest.fixture(scope="session")
def marcus():
    """(Scenario, World, Mission) of the real marcus-wake scenario."""
    s = sc.load("marcus-wake")
    w, m = sc.build(s)
    return s, w, m


@pytest.fixture(scope="session")
def salish():
    """(Scenario, World, Mission) of the real salish-shelf scenario."""
    s = sc.load("salish-shelf")
    w, m = sc.build(s)
    return s, w, m
