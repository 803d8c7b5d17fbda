"""What ``tools/mutate.py`` mutates: per safety-relevant module, the functions that decide safety and
the tests that guard them (the module's oracle and fast unit tests, run with ``NUMBA_DISABLE_JIT=1``;
not the whole suite, so a module's score is a lower bound of the whole suite's)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Target:
    """Functions ``(python module, "function" or "Class.method")`` and the pytest arguments that guard them."""

    functions: tuple[tuple[str, str], ...]
    tests: tuple[str, ...]
    jit: bool = True  # False where the mutated functions are numba kernels (they then run as Python)


def _fns(module: str, *names: str) -> tuple[tuple[str, str], ...]:
    return tuple((module, n) for n in names)


TERRAIN = "auvplan.world.terrain"
WORLD, OBSTACLES = "auvplan.world.world", "auvplan.world.obstacles"
COST = "auvplan.cost"
GRID = "auvplan.planners.grid"
SIM = "auvplan.sim"
LOCAL = "auvplan.guidance.local"
FLOW, STREAM = "auvplan.planners.flow", "auvplan.planners.flow_stream"

MODULES: dict[str, Target] = {
    # the exact segment-vs-seabed test, its Lipschitz shortcut and the bilinear surface
    "terrain": Target(
        _fns(TERRAIN, "Terrain.__post_init__", "Terrain.altitude", "Terrain.altitude_lower_bound",
             "Terrain.min_altitude_between", "Terrain.segments_below", "_cell", "elevation_kernel", "_piece_min",
             "_crossings", "_walk_min", "min_altitude_kernel", "_min_altitudes"),
        ("tests/test_oracles.py", "tests/test_terrain.py", "-k",
         "ridge or slope or terrain or bilinear or gradient or outside or lower_bound",
         "--deselect", "tests/test_terrain.py::test_exact_segment_test_agrees_with_dense_sampling"),
        jit=False,
    ),
    # the World's point and segment tests and the obstacles' exact distances and segment tests
    "world": Target(
        _fns(WORLD, "Bounds.slack", "Bounds.contains", "World.clearances", "World._obstacle_slack",
             "World.clearance", "World.is_free", "World.segments_free", "World.path_free")
        + _fns(OBSTACLES, "Sphere.distance", "Sphere.segments_hit", "Ellipsoid._foot_point", "Ellipsoid.distance",
               "Ellipsoid.lower_bound_distance", "Ellipsoid.segments_hit", "Ellipsoid._segment_min_distance"),
        ("tests/test_world.py", "tests/test_oracles.py", "-k",
         "not lamb_oseen and not gridded and not current and not iabc and not sbx and not polynomial"),
    ),
    # the energy/duration kernel and the path terms (violations, clearance)
    "cost": Target(
        _fns(COST, "_obstacle_slack", "segment_energy", "energy_kernel", "_segment_energies", "_point_slack",
             "_path_terms", "evaluate_paths"),
        ("tests/test_cost.py", "tests/test_oracles.py", "-k", "cost or energy or seabed"),
        jit=False,
    ),
    # lattice edge generation (collision tests), edge weights and the Dijkstra search
    "grid": Target(
        _fns(GRID, "_edge_weight", "_sift_up", "_sift_down", "_search", "free_edges",
             "GridReference._lattice_edges", "GridReference._connect"),
        ("tests/test_oracles.py", "tests/test_grid.py", "-k",
         "edge or cost_to_go or empty or enclosed"),
        jit=False,
    ),
    # the simulation's event detection (collision, arrival, deadlock, timeout)
    "sim": Target(
        _fns(SIM, "_distance", "_obstacle_shapes", "simulate"),
        ("tests/test_oracles.py", "tests/test_tracking.py", "-k",
         "seabed or collision or converges or deadlock_is_declared or arrival_at"),
    ),
    # document 004's local avoidance: key waypoints (collision checks), APF, minimum detection, escapes
    "local": Target(
        _fns(LOCAL, "key_waypoints", "apf_force", "MinimumDetector.update", "_random_free_point",
             "LocalAvoidance._escape", "LocalAvoidance.stalled", "LocalAvoidance._advance_goal",
             "LocalAvoidance.command", "LocalAvoidance._apf_command"),
        ("tests/test_oracles.py", "tests/test_local.py", "-k",
         "apf or key_waypoints or head_on or crossing or repulsion or parked or removed or fast_obstacle"),
    ),
    # the planner's flow field (sphere image solution, clearance) and the streamlines' stop conditions
    "flow": Target(
        _fns(FLOW, "sink_velocity", "sphere_exact_velocity", "FlowField.clearance", "FlowField.inside_body",
             "FlowField.push_out", "FlowField._sphere_parts", "FlowField._free", "FlowField.velocity")
        + _fns(STREAM, "_segment_clear", "_exit_body", "_deflect", "integrate_streamlines"),
        ("tests/test_oracles.py", "tests/test_flow.py", "-k",
         "sphere_field or exact_field or tip_and_axis or on_axis_sphere or inside_the_inflated or plan_flow_status"),
    ),
}

# Why each surviving mutant survives, keyed ``"function | before -> after"`` (the text ``mutate.py``
# prints): an equivalent mutant (no input can tell it apart) or one the tests cannot observe.
REASONS: dict[str, str] = {
}
