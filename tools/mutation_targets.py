"""What ``tools/mutate.py`` mutates: per safety-relevant module, the functions that decide safety.

The tests: every test file that imports a mutated module (``Target.tests`` empty; see
:func:`mutate.importing_tests`), minus the tests slower than ``--test-limit`` CPU seconds unmutated.
The older targets (terrain ... flow) named their tests one by one until issue #31; those lists are
kept in ``LISTED`` for re-running the older records' selection (``--listed``)."""

from __future__ import annotations

from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Target:
    """Functions ``(python module, "function" or "Class.method"[, first marker, end marker])`` and the
    pytest arguments that guard them; with markers, only the lines from the one holding the first
    marker up to the one holding the end marker are mutated."""

    functions: tuple[tuple[str, ...], ...]
    tests: tuple[str, ...] = ()  # empty: every test file importing a mutated module
    jit: bool = True  # False where the mutated functions are numba kernels (they then run as Python)


def _fns(module: str, *names: str) -> tuple[tuple[str, str], ...]:
    return tuple((module, n) for n in names)


TERRAIN, TERRAIN_KERNELS = "auvplan.world.terrain", "auvplan.world.kernels.terrain"
WORLD, OBSTACLES = "auvplan.world.world", "auvplan.world.obstacles"
WORLD_LIMITS = "auvplan.world.limits"
COST_ENERGY, COST_PATHS = "auvplan.cost.energy", "auvplan.cost.paths"
GRID = "auvplan.planners.grid.reference"
NODES, EDGES = "auvplan.planners.grid.lattice.nodes", "auvplan.planners.grid.lattice.edges"
DIJKSTRA = "auvplan.planners.grid.lattice.dijkstra"
HEAP = "auvplan.planners.grid.heap"
SIM_EVENTS, SIM_LOOP = "auvplan.sim.events", "auvplan.sim.loop"
LOCAL = "auvplan.guidance.avoidance.local"
FLOW, STREAM = "auvplan.planners.flow.field", "auvplan.planners.flow.stream"
ELEMENTS = "auvplan.planners.flow.elements"
ENVELOPES, FLYCHECK = "auvplan.guidance.mission.envelopes", "auvplan.guidance.mission.flycheck"
LIMITS = "auvplan.guidance.mission.limits"
FORMATS, PARSERS = "auvplan.io.missions.readback.readers", "auvplan.io.missions.readback.parsers"
FORMATION = "auvplan.sim.formation"

MODULES: dict[str, Target] = {
    # the exact segment-vs-seabed test, its Lipschitz shortcut and the bilinear surface
    "terrain": Target(
        _fns(TERRAIN, "Terrain.__post_init__", "Terrain.altitude", "Terrain.altitude_lower_bound",
             "Terrain.min_altitude_between", "Terrain.segments_below")
        + _fns(TERRAIN_KERNELS, "_cell", "elevation_kernel", "_piece_min", "_crossings", "_walk_min",
               "min_altitude_kernel", "_min_altitudes"),
        ("tests/oracles/test_oracles.py", "tests/oracles/test_terrain.py", "-k",
         "ridge or slope or terrain or bilinear or gradient or outside or lower_bound or offset_grid or off_the_grid"
         " or altitude_limit or twisted_cell or more_rows_than_columns",
         "--deselect", "tests/oracles/test_terrain.py::test_exact_segment_test_agrees_with_dense_sampling"),
        jit=False,
    ),
    # the World's point and segment tests and the obstacles' exact distances and segment tests
    "world": Target(
        _fns(WORLD_LIMITS, "Bounds.slack", "Bounds.contains")
        + _fns(WORLD, "World.clearances", "World._obstacle_slack",
             "World.clearance", "World.is_free", "World.segments_free", "World.path_free")
        + _fns(OBSTACLES, "Sphere.distance", "Sphere.segments_hit", "Ellipsoid._foot_point", "Ellipsoid.distance",
               "Ellipsoid.lower_bound_distance", "Ellipsoid.segments_hit", "Ellipsoid._segment_min_distance"),
        ("tests/unit/test_world.py", "tests/oracles/test_oracles.py", "tests/oracles/test_oracles_sim.py", "-k",
         "not lamb_oseen and not gridded and not current and not iabc and not sbx and not polynomial"
         " and (not oracles_sim or world_)"),
    ),
    # the energy/duration kernel and the path terms (violations, clearance)
    "cost": Target(
        _fns(COST_PATHS, "_obstacle_slack") + _fns(COST_ENERGY, "segment_energy", "energy_kernel", "_segment_energies")
        + _fns(COST_PATHS, "_point_slack", "_path_terms", "evaluate_paths"),
        ("tests/oracles/test_cost.py", "tests/oracles/test_oracles.py", "-k", "cost or energy or seabed"),
        jit=False,
    ),
    # the lattice (planners/grid/lattice/): free nodes and their safe single-precision fields, the edge
    # test's shortcut (seabed Lipschitz bound, obstacle distance) and its exact fallback, edge bits,
    # edge weights, the indexed binary heap and the Dijkstra/A* search, the free-edge list; and
    # the links of the goal and starts to the lattice
    "grid": Target(
        _fns(NODES, "down32", "node_fields") + _fns(EDGES, "_offset_states", "edge_states", "_set_bits", "edge_bits")
        + _fns(DIJKSTRA, "_edge_weight", "_heuristic", "_settle_link", "_search", "search") + _fns(EDGES, "free_edges")
        + _fns(HEAP, "_sift_up", "_sift_down", "push", "pop")
        + _fns(GRID, "GridReference._connect"),
        tuple(f"tests/oracles/test_oracles.py::test_{t}" for t in (
            "every_edge_of_the_cost_to_go_tree_is_free", "grid_costs_each_edge_in_its_own_direction",
            "cost_to_go_equals_scipys_dijkstra_over_the_free_lattice",
            "grid_costs_with_a_weaker_current_with_a_vertical_part",
            "free_edges_are_exactly_the_free_lattice_segments"))
        + tuple(f"tests/oracles/test_grid.py::test_{t}" for t in (
            "empty_world_gives_the_straight_line", "cost_to_go_is_the_26_connected_lattice_distance",
            "goal_enclosed_by_terrain_is_infeasible_with_a_message"))
        + ("tests/unit/test_lattice.py::test_compiled_edge_test_agrees_with_the_exact_segment_test_on_every_edge",)
        + tuple(f"tests/oracles/test_oracles_sim.py::test_lattice_{t}" for t in (
            "edges_across_a_seabed_ridge_are_exactly_the_free_segments", "heap_pops_in_heapq_order_with_decrease_key",
            "sift_down_reads_nothing_past_the_heap_end", "search_is_scipys_dijkstra_with_random_currents_and_edges",
            "search_by_length_on_a_line", "fields_round_down_to_the_nearest_single",
            "node_fields_are_the_worlds_static_clearances", "astar_heuristic_is_c_min_times_the_distance_to_the_start",
            "astar_finds_each_starts_dijkstra_cost_on_an_obstacle_lattice")),
        jit=False,
    ),
    # the simulation's event detection (collision, arrival, deadlock, timeout): the pure event rules
    # and the loop's per-step events (the rest of the loop records the run and steps the vehicle)
    "sim": Target(
        _fns(SIM_EVENTS, "_distance", "_obstacle_shapes", "_contact_event", "_arrived", "_progressed", "_deadlocked")
        + _fns(SIM_LOOP, "_step_events"),
        tuple(f"tests/oracles/test_oracles.py::test_{t}" for t in (
            "a_dive_into_the_seabed_ends_in_collision", "deadlock_is_declared_one_step_after_the_deadlock_time",
            "arrival_at_the_radius_and_timeout_at_max_time", "collision_names_the_obstacle_that_was_hit",
            "the_moving_obstacle_that_hits_decides_unavoidable"))
        + ("tests/oracles/test_tracking.py::test_converges_to_the_route_exponentially",
           "tests/oracles/test_tracking.py::test_collision_is_reported_as_a_status",
           "tests/unit/test_local.py::test_fast_obstacle_aimed_at_the_vehicle_is_unavoidable")
        + tuple(f"tests/oracles/test_oracles_sim.py::test_sim_{t}" for t in (
            "contact_is_penetration_and_names_what_was_hit",
            "moving_hit_is_unavoidable_when_at_least_as_fast_and_closing_in",
            "arrival_progress_and_deadlock_rules_at_their_boundaries", "a_creeping_vehicle_is_not_deadlocked",
            "an_obstacle_on_the_seabed_hit_half_a_metre_above_it")),
    ),
    # document 004's local avoidance: key waypoints (collision checks), APF, minimum detection, escapes
    "local": Target(
        _fns(LOCAL, "key_waypoints", "apf_force", "MinimumDetector.update", "_random_free_point",
             "LocalAvoidance._escape", "LocalAvoidance.stalled", "LocalAvoidance._advance_goal",
             "LocalAvoidance.command", "LocalAvoidance._apf_command"),
        ("tests/oracles/test_oracles.py", "tests/unit/test_local.py", "tests/oracles/test_oracles_sim.py", "-k",
         "(apf or key_waypoints or head_on or crossing or repulsion or parked or removed or fast_obstacle"
         " or escape_sub_goal or minimum_detector or local_) and (not oracles_sim or local_)"),
    ),
    # the planner's flow field (sphere image solution, clearance) and the streamlines' stop conditions
    "flow": Target(
        _fns(ELEMENTS, "sink_velocity", "sphere_exact_velocity")
        + _fns(FLOW, "FlowField.clearance", "FlowField.inside_body",
             "FlowField.push_out", "FlowField._sphere_parts", "FlowField._free", "FlowField.velocity")
        + _fns(STREAM, "_segment_clear", "_exit_body", "_deflect", "integrate_streamlines", "_Run.start",
               "_Run.advance", "_Run.sideways", "_Run.step", "_direction", "_rk4", "_guarded_rk4"),
        # the field's oracle tests, test_oracles_flow.py (the mirror sink, push_out on a body, the exit rule
        # in a sphere's shell, the step cap, stagnation, the front rule's threshold, grazes) and the whole of
        # test_flow.py (~20 s: starts inside bodies, the on-axis rule, the seabed plane, streamlines that must
        # never enter a body)
        ("tests/oracles/test_oracles.py::test_planner_sphere_field_is_the_exact_image_solution",
         "tests/oracles/test_oracles.py::test_planner_sphere_field_clearance_and_the_sink_by_hand",
         "tests/oracles/test_oracles.py::test_push_out_puts_points_on_the_ray_from_the_centre_just_outside_the_flow_sphere",
         "tests/oracles/test_oracles.py::test_streamline_segment_clear_is_the_sampled_flow_clearance",
         "tests/oracles/test_oracles.py::test_exit_rule_leaves_a_line_distribution_body_just_outside_its_surface",
         "tests/oracles/test_oracles_flow.py", "tests/oracles/test_flow.py"),
    ),
}

# issue #31: every target runs against the test files that import it; the lists above were hand-picked
LISTED: dict[str, tuple[str, ...]] = {name: t.tests for name, t in MODULES.items()}
MODULES = {name: replace(t, tests=()) for name, t in MODULES.items()}
MODULES.update({
    # the mission envelope (exact seabed, exact rectangle-vs-obstacle), the re-flying check and its verdict,
    # the executor model, and the surface / depth band / bounds at the waypoints
    "mission": Target(
        _fns(ENVELOPES, "leg_floors", "_unit_frame", "_parallelogram_distance", "envelope_corners", "envelope_hits",
             "envelopes_free", "_sphere_rect_distance", "_sampled_rect_distance", "rect_distance")
        + _fns(FLYCHECK, "MissionCheck.ok", "held_track", "fly_check")
        + _fns(LIMITS, "WaypointLimits.ok", "waypoint_limits"),
    ),
    # the mission readers: what `mission check` re-flies is what these parse
    "formats": Target(
        _fns(PARSERS, "_moos_blocks", "parse_moos", "parse_qgc_plan", "parse_gpx", "parse_ros_path",
             "_geojson_mission", "_kml_mission") + _fns(FORMATS, "read_mission", "check_mission_file"),
    ),
    # the formation loop's contact rule and the stop it causes
    "formation": Target(
        _fns(FORMATION, "_contact") + ((FORMATION, "_Fleet._vehicle", "what = _contact(", "if (self.arrived[0]"),),
    ),
    # the cost's constraint kernel: point slack (depth band, bounds), obstacle slack, path terms
    # (its importing files, test_planner.py and the whole of test_oracles.py with the kernels as Python, did
    # not fit issue #31's session on the shared machine: run against the cost target's tests + test_safety.py)
    "cost-constraints": Target(
        _fns(COST_PATHS, "_point_slack", "_obstacle_slack", "_path_terms"),
        ("tests/oracles/test_cost.py", "tests/oracles/test_oracles.py", "tests/oracles/test_safety.py",
         "-k", "cost or energy or seabed or "
         "test_safety"),
        jit=False,
    ),
})

# issue #49: the modules of the survey / endurance / uncertainty / serve / geographic-input / vehicle-limits /
# ladder / tail-first wave, each against every test file that imports it (the list of targets the issue asks for)
UNCERTAINTY, SERVE_BUDGET, SERVE_LRU = "auvplan.world.uncertainty", "auvplan.app.page.budget", "auvplan.app.page.lru"
BUDGET, PNR, POWER = "auvplan.endurance.budget", "auvplan.endurance.pnr", "auvplan.endurance.power"
SPEEDS = "auvplan.endurance.speeds"
FLYABLE, PLAN_LIMITS = "auvplan.path.flyable", "auvplan.planners.core.vehicle_limits"
GEOINPUT, LADDER = "auvplan.io.scenario.inputs.geoinput", "auvplan.planners.grid.ladder"
TURNS, TAIL_IO, TAIL_PLAN = "auvplan.survey.turns", "auvplan.io.missions.tail", "auvplan.planners.timeopt.tail"
REPLAN = "auvplan.sim.ensemble.replan"
MODULES.update({
    # the bathymetric uncertainty: the slope rule's sigma and the worst-case seabed
    "uncertainty": Target(_fns(UNCERTAINTY, "z_score", "slope_sigma", "worst_case")),
    # serve's energy cache: which fields are steady, the cached budget, the LRU
    "serve-budget": Target(
        _fns(SERVE_BUDGET, "steady", "IncrementalBudget.run") + _fns(SERVE_LRU, "LruCache.get_many", "LruCache.put"),
    ),
    # the energy budget (ground speed, the flight through the currents, the verdict), the power model and
    # the point of no return
    "endurance": Target(
        _fns(BUDGET, "ground_speed", "traverse", "budget_of", "Traverse.at")
        + _fns(POWER, "optimal_speed", "EnergyModel.power")
        + _fns(PNR, "return_route", "_return_energy", "point_of_no_return"),
    ),
    # the vehicle's limits: pitch, fly-by turns, the check, merging; the planners' repair
    "vehicle-limits": Target(
        _fns(FLYABLE, "leg_pitch_deg", "turn_angles", "leg_turn_radius", "check_limits", "corner_indices",
             "merge_close", "flyby_arcs")
        + _fns(PLAN_LIMITS, "vertex_floors", "repair_pitch", "enforce_limits"),
    ),
    # geographic input: the derived origin (antimeridian), positions, the derived bounds, the data's sides
    "geoinput": Target(
        _fns(GEOINPUT, "bounds_margin", "_geo_point", "_derive_origin", "resolve_positions", "apply_altitudes",
             "clip_to_data"),
    ),
    # the survey's turns between lines (Dubins)
    "survey-turns": Target(_fns(TURNS, "_mod", "_words", "dubins", "sample_turn")),
    # the ladder of lattices: the rungs' cells and which rung wins (issue 49's measured run: --tests
    # tests/unit/test_ladder_by_hand.py tests/property/test_edges_properties.py::test_the_cheapest_rung_wins_the_ladder)
    "ladder": Target(_fns(LADDER, "_cells", "plan_ladder")),
    # tail-first legs: the planner's tail speed and the mission files' flags (measured: --tests
    # tests/unit/test_tail_by_hand.py; tail_speed is a kernel: only its Python function, tail_speed.py_func, is
    # seen mutated with the JIT on, as the compiled callers keep the original)
    "tail-first": Target(_fns(TAIL_PLAN, "tail_speed") + _fns(TAIL_IO, "any_tail", "refusal", "read_tail")),
    # the re-planning flight's verdict
    "replan": Target(_fns(REPLAN, "_finish", "Flight.arrived", "Flight.success")),
})

# Why each surviving mutant survives, keyed ``"function | before -> after"`` (the text ``mutate.py``
# prints): an equivalent mutant (no input can tell it apart) or one the tests cannot observe.
_NEG = "equivalent: numpy infers the length of any negative dimension, -2 as -1"
_UNUSED_W = ('equivalent: without a cost (length objective) the kernel is told use_cost = False and returns th'
             'e edge length before reading these weights')
_KNOWN = ("equivalent in use: the caller's end altitudes are the true ones, which the kernel would compute "
          "itself (only World.segments_free passes them on)")
_CELL = "equivalent: at the boundary both branches give the same cell index"
_EDGE = ("equivalent: reached only with the piece's midpoint outside the grid, where the mutated test "
         "answers the same")
_GRAZE = ("equivalent: a step still entering a surface after six quarterings starts at a node outside (d >= 0, "
          "only such nodes are kept) and is at most h_min / 4096 long, so it ends at most h_min / 4096 inside "
          "(d is 1-Lipschitz, up to a body profile's chord sag); every graze window at least that wide (0.02 h_min "
          "here) corrects the same grazes")
_ONES = "equivalent: an all-True answer has no blocked index, whatever its length"
_LAST = ("equivalent: i never exceeds n - 1, and at i = n - 1 the next pass has no segment left and stops "
         "with the same keys")
_BOX = ("equivalent in outcome: the box only narrows which settled nodes are compared with the start's links; "
        "a wider box costs needless comparisons, a narrower one only delays A*'s stop (same costs, more nodes "
        "settled)")
_HEUR = ("**not killed**: a wrong A* heuristic; on the test lattices (at most 9 x 8 x 6 nodes with A*) it still "
         "finds the start's cheapest cost")
_STARTLINK = ("**not killed**: A*'s check of a settled node against the start's links; on the test lattices the "
              "search still reaches the start's cheapest cost")
_AXIS = "equivalent: the arrays are (K, 3) (or (K, 2)), where axis 1 is axis -1"
_UNUSED_SAFE = ("equivalent: where ok is False the s and t computed with this divisor are discarded "
                "(inside = ok & ...)")
_ON_EDGE = ("equivalent: at s or t exactly 0 or 1 the foot of the perpendicular lies on an edge of the "
            "parallelogram, whose segment distance is the same as the plane's")
REASONS: dict[str, str] = {
    # terrain
    "Terrain.__post_init__ | if not np.any(step > 0) or not np.allclose(step, step[0], rtol=1e-06, atol=1e-09):":
        "equivalent: steps that pass the uniform-spacing test all have one sign (unless all are below the "
        "1e-9 m tolerance), so any = all",
    "Terrain.altitude_lower_bound | return np.minimum(bound, np.maximum(ga, gb))":
        "equivalent: with true end altitudes and the true slope, |g_a - g_b| <= |Δz| + G L_h, so the bound "
        "(g_a + g_b - |Δz| - G L_h)/2 is already <= min(g_a, g_b): the outer minimum never decides",
    "Terrain.min_altitude_between | a = np.ascontiguousarray(a.reshape(-2, 3))": _NEG,
    "Terrain.min_altitude_between | b = np.ascontiguousarray(b.reshape(-2, 3))": _NEG,
    "Terrain.min_altitude_between | ga, gb = (np.ascontiguousarray(np.broadcast_to(np.asarray(g, dtype=float), "
    "lead).reshape(-2)) for g in end_altitudes)": _NEG,
    "Terrain.min_altitude_between | known = False": _KNOWN,
    "_cell | return 0 if i <= 0 else cells - 1 if i > cells - 1 else int(i)": _CELL,
    "_cell | return 0 if i < 1 else cells - 1 if i > cells - 1 else int(i)": _CELL,
    "_cell | return 0 if i < 0 else cells - 1 if i >= cells - 1 else int(i)": _CELL,
    "_cell | return 0 if i < 0 else cells - 1 if i > cells - 2 else int(i)": _CELL,
    "_piece_min | u0, du = (0.0 if fx <= 0.0 else 1.0, 0.0)": _EDGE,
    "_piece_min | v0, dv = (0.0 if fy <= 0.0 else 1.0, 0.0)": _EDGE,
    "_piece_min | v0, dv = (0.0 if fy < 1.0 else 1.0, 0.0)": _EDGE,
    "_piece_min | if fy < 0.0 or fy >= nyc:":
        "equivalent: a piece whose midpoint lies exactly on the last grid line runs along it (dv = 0) "
        "with v = 1 either way",
    "_piece_min | if fx <= 0.0 or fx > nxc:": _EDGE,
    "_piece_min | if fx < 0.0 or fx >= nxc:": _EDGE,
    "_piece_min | u0, du = (0.0 if fx < 1.0 else 1.0, 0.0)": _EDGE,
    "_piece_min | if fy <= 0.0 or fy > nyc:": _EDGE,
    "_piece_min | if g2 >= 0.0:": "equivalent: with g2 = 0 the vertex -g1 / (2 g2) is ±inf or NaN (numpy floats), "
        "never inside (ta, tb)",
    "_piece_min | if g2 > 1.0:": "**not killed** (no oracle yet): a twisted cell whose altitude along the segment is "
        "a parabola of curvature g2 in (0, 1] m has its interior minimum skipped (unsafe)",
    "_piece_min | if ta <= tv < tb:": "equivalent: at tv = ta the vertex value is the end value already taken",
    "_piece_min | if ta < tv <= tb:": "equivalent: at tv = tb the vertex value is the end value already taken",
    "_crossings | return (max(math.floor(ka) + 1.0, 0.0), max(math.ceil(kb) - 1.0, float(lines)), 1.0, ka, kb)":
        "equivalent: extra split points beyond the last grid line only cut pieces whose minima are exact anyway",
    "_crossings | return (max(math.floor(ka) + 1.0, 0.0), min(math.ceil(kb) + 1.0, float(lines)), 1.0, ka, kb)":
        "equivalent: the extra crossings lie beyond the segment's end (t > 1), where the walk stops",
    "_crossings | return (min(math.ceil(ka) - 1.0, float(lines)), min(math.floor(kb) + 1.0, 0.0), -1.0, ka, kb)":
        "equivalent: extra split points below the first grid line only cut pieces whose minima are exact anyway",
    "_crossings | return (min(math.ceil(ka) - 1.0, float(lines)), max(math.floor(kb) - 1.0, 0.0), -1.0, ka, kb)":
        "equivalent: the extra crossing lies beyond the segment's end (t > 1), where the walk stops",
    "_crossings | if kb <= ka:": "equivalent: with kb = ka the descending branch also yields no crossing",
    "_crossings | return (2.0, 0.0, 1.0, ka, kb)": "equivalent: first > last still means no crossing",
    "_crossings | return (1.0, 0.0, 2.0, ka, kb)": "equivalent: (last - first) x 2 < 0 still means no crossing",
    "_walk_min | tx = (kx - kxa) / (kxb - kxa) if (kx_end - kx) / sx >= 0.0 else 2.0":
        "equivalent: sx is ±1, so / sx = * sx",
    "_walk_min | ty = (ky - kya) / (kyb - kya) if (ky_end - ky) / sy >= 0.0 else 2.0":
        "equivalent: sy is ±1, so / sy = * sy",
    "_walk_min | tx = (kx - kxa) / (kxb - kxa) if (kx_end - kx) * sx >= 0.0 else 3.0":
        "equivalent: any value > 1 means 'no more crossings' (tb = min(tx, ty, 1))",
    "_walk_min | ty = (ky - kya) / (kyb - kya) if (ky_end - ky) * sy >= 0.0 else 3.0":
        "equivalent: any value > 1 means 'no more crossings' (tb = min(tx, ty, 1))",
    "_walk_min | ky, ky_end, sy, kya, kyb = _crossings(py, qy, y0, dy, coef.shape[1])":
        "**not killed** (no oracle yet): caps the y crossings at the number of x cells; the oracle grids have "
        "more x than y cells, where it only adds split points; a grid with more y cells would lose splits",
    # cost
    "_obstacle_slack | ends = np.stack([a, b], axis=2)":
        "equivalent: the segment arrays are always (P, S - 1, 3), where axis 2 is axis -2",
    "energy_kernel | t = ds / (speed if blocked or vg <= 0.0 else vg) if ds >= 0.0 else 0.0":
        "equivalent: a zero-length segment takes 0 / (a positive speed) = 0 s either way",
    "_path_terms | if slack <= 0.0:": "equivalent: at slack = 0 the violation depth grows by 0",
    # local
    "key_waypoints | if p.shape[0] <= 2:":
        "equivalent: with two points the loop keeps both as well (first and last are always kept)",
    "key_waypoints | if p.shape[0] < 3:":
        "equivalent: with two points the loop keeps both as well (first and last are always kept)",
    "key_waypoints | if p.shape[1] < 2:":
        "equivalent: p.shape[1] is 3; a single point then goes through the loop, which returns it alone",
    "apf_force | c = np.asarray(centers, dtype=float).reshape(-2, 3)": _NEG,
    # flow
    "_exit_body | for _ in range(61):":
        "equivalent: a 61st halving moves the exit point by 2^-61 of the body's diameter, below float resolution",
    "_exit_body | for _ in range(5):":
        "not killed: a 5th push matters only for a start whose exit lands in a second, third and fourth flow "
        "surface in a row; a start left inside a surface then stops by the step-retry/contact rule (not unsafe)",
    "_deflect | if field.distances(cand[ok][None], 'true').max() > 0 and field.distances(0.5 * (x[i] + "
    "cand[ok])[None], 'true').min() > 0:":
        "not killed (no oracle): needs a sideways step (0.06 R) ending inside a second flow surface with its "
        "midpoint outside all, i.e. an obstacle under ~0.1 R at the front stagnation point of a larger one; "
        "the step is recorded in min_distance and plan_flow's exact segment test would reject the path",
    "_deflect | near = (d[sel, k] < max(2.0 * h_min, 0.02 * R)) & (along < 0) & (rho <= 0.05 * R)":
        "boundary: a streamline exactly 0.05 R off the axis",
    "integrate_streamlines | run = _Run.start(field, np.array(starts, dtype=float).reshape(-2, 3), "
    "params.max_steps + 1)": _NEG,
    "FlowField.clearance | near = lb <= max(ob.semi_axes)":
        "boundary: differs only where the lower bound equals the largest semi-axis exactly; the exact distance "
        "(>= the bound) is then returned instead of the bound",
    "FlowField.push_out | inside = self.distances(q[todo], 'true')[np.arange(todo.size), k[todo]] <= 0":
        "boundary: a pushed point exactly on its surface (distance 0.0) gets one more doubling of the margin",
    "FlowField.push_out | continue":
        "equivalent: once no point is inside, the remaining doublings have no point to move and change nothing",
    "FlowField.push_out | k = d.argmin(axis=1)": "equivalent: d is (N, K) here (p is reshaped to (N, 3)), axis 1 "
        "is axis -1",
    "_guarded_rk4 | for _ in range(7):":
        "not killed: a seventh quartering (h / 16384) only lets a streamline creeping into a leaky surface take "
        "one more tiny step before the graze correction; its nodes stay outside either way",
    "_guarded_rk4 | graze = np.flatnonzero((d_next < 0) & (d_next >= -0.001 * h_min / 0.05))": _GRAZE,
    "_guarded_rk4 | graze = np.flatnonzero((d_next < 0) & (d_next > -1.001 * h_min / 0.05))": _GRAZE,
    "_guarded_rk4 | graze = np.flatnonzero((d_next < 0) & (d_next > -0.001 / h_min / 0.05))":
        _GRAZE + " (here 0.02 / h_min >= h_min / 4096 for h_min <= 9 m, i.e. obstacles up to ~180 m)",
    "FlowField.inside_body | return np.asarray((d <= 0).any(axis=-1) if d.shape[-1] else np.zeros(d.shape[:-1], "
    "dtype=bool))":
        "boundary: a point exactly on a flow surface (distance 0.0), which the exit rule then leaves as it is",
    "FlowField.push_out | n[i] = self.bodies[j - ns].normal(p[i:i + 2])[0] if self.contained else "
    "self.items[j].gradient(p[i])": "equivalent: row 0 of the normals of p[i:i + 2] is the normal at p[i]",
    "FlowField._sphere_parts | b = np.linalg.norm(Tc, axis=1)": "equivalent: Tc is (S, 3), axis 1 is axis -1",
    "FlowField._free | mirror = self.target / np.array([1.0, 1.0, -1.0]) + np.array([0.0, 0.0, 2.0 * self.plane])":
        "equivalent: dividing by ±1 is multiplying by ±1",
    "FlowField.velocity | p = p.reshape(-2, 3)": _NEG,
    "_deflect | near = (d[sel, k] < max(2.0 * h_min, 0.02 * R)) & (along <= 0) & (rho < 0.05 * R)":
        "boundary: a streamline exactly in the plane through the obstacle's centre square to the axis",
    "_deflect | if field.distances(cand[ok][None], 'true').min() >= 0 and field.distances(0.5 * (x[i] + "
    "cand[ok])[None], 'true').min() > 0:": "boundary: a sideways step ending exactly on a flow surface",
    "_deflect | if field.distances(cand[ok][None], 'true').min() > 0 and field.distances(0.5 * (x[i] + "
    "cand[ok])[None], 'true').min() >= 0:": "boundary: a sideways step whose midpoint lies exactly on a flow surface",
    "_deflect | if field.distances(cand[ok][None], 'true').min() > 0 and field.distances(0.5 * (x[i] + "
    "cand[ok])[None], 'true').max() > 0:":
        "not killed (no oracle): needs a sideways step whose midpoint lies inside a second flow surface while its "
        "end is outside all (an obstacle under ~0.1 R at the front stagnation point of a larger one); the "
        "planner's exact segment test would still reject the path",
    "_direction | sp = np.linalg.norm(u, axis=1, keepdims=True)":
        "equivalent: the points are (N, 3) here, axis 1 is axis -1",
    "_Run.step | d = dall.min(axis=-1) if dall.shape[1] else np.full(idx.size, np.inf)":
        "equivalent: dall is (N, K) here, axis 1 is axis -1",
    "_Run.step | stalled = sp <= params.stagnation * ref":
        "boundary: a speed exactly at the stagnation fraction of the bare sink's",
    "FlowField.push_out | p = np.array(p, dtype=float).reshape(-2, 3)": _NEG,
    "_deflect | s = np.where((rho >= 1e-09 * R)[:, None], perp / np.maximum(rho, 1e-300)[:, None], field.sides[k])":
        "boundary: a streamline exactly 1e-9 R off the axis",
    "_deflect | if field.distances(cand[ok][None], 'true').min() > 0 or field.distances(0.5 * (x[i] + "
    "cand[ok])[None], 'true').min() > 0:":
        "not killed (no oracle): differs only when one of the sideways step's end and midpoint lies inside a flow "
        "surface and the other not (a second obstacle under ~0.1 R at the front of a larger one; see above)",
    "_Run.step | arrived = dist_goal < params.arrive": "boundary: a node exactly at the arrival radius",
    "_Run.step | missed = ((x - T) @ field.direction >= 0) & ~arrived":
        "boundary: a node exactly in the goal's plane (uniform field)",
    "_guarded_rk4 | graze = np.flatnonzero((d_next < 0) & (d_next > -0.001 * h_min / 1.05))": _GRAZE,
    "_Run.step | contact = (d_next < 0) | (self.corrections[idx] > MAX_CORRECTIONS) | (clear_next <= 0)":
        "boundary: a node whose clearance is exactly 0.0",
    "FlowField.velocity | if parts.shape[2] == 1:":
        "equivalent: a single field then goes through the blend, whose one weight is exactly 1.0 (both weight "
        "kinds; distances floored at 1e-12)",
    "_exit_body | if d[j] > 0:": "boundary: a start exactly on a flow surface (distance 0.0)",
    "_exit_body | lo, hi = (0.0, 3.0 * body.radius)":
        "equivalent to float resolution: the bisection converges on the same crossing (the ray from inside leaves "
        "the body within its diameter), to 3 R / 2^60 instead of 2 R / 2^60",
    "_deflect | near = (d[sel, k] <= max(2.0 * h_min, 0.02 * R)) & (along < 0) & (rho < 0.05 * R)":
        "boundary: a node exactly at the rule's distance threshold",
    "_deflect | s = np.where((rho > 1e-09 / R)[:, None], perp / np.maximum(rho, 1e-300)[:, None], field.sides[k])":
        "boundary: differs only for a streamline between 1e-9 / R and 1e-9 R off the axis (nanometres)",
    "_Run.sideways | far = np.linalg.norm(self.p[idx] - field.target, axis=1) >= arrive":
        "boundary: a node exactly at the arrival radius",
    "_Run.sideways | defl &= far & (self.deflections[idx] <= MAX_DEFLECTIONS)":
        "not killed: needs a streamline sent sideways 20 times (bouncing between obstacles' fronts)",
    "_Run.step | d = dall.min(axis=1) if dall.shape[-1] else np.full(idx.size, np.inf)":
        "equivalent: dall is (N, K) here, axis 1 is axis -1",
    "_guarded_rk4 | graze = np.flatnonzero((d_next <= 0) & (d_next > -0.001 * h_min / 0.05))":
        "boundary: differs only for a step ending exactly on a flow surface (distance 0.0), which is then moved "
        "1e-9 R outside and counted as a correction",
    # grid
    "node_fields | step = min(1, _SLAB // (shape[1] * shape[2]))":
        "equivalent: one x row per slab; the slab size changes only memory and time",
    "node_fields | step = max(2, _SLAB // (shape[1] * shape[2]))":
        "equivalent: the slab size changes only memory and time",
    "node_fields | step = max(1, _SLAB // (shape[2] * shape[2]))":
        "equivalent: the slab size changes only memory and time",
    "node_fields | cur[i0 * n:i1 * n] = world.currents.velocity(pts).reshape(-2, 3)": _NEG,
    "_offset_states | sure = min(obs[i, j, k], obs[vi, vj, vk]) > half_length":
        "equivalent: the shortcut only decides which edges skip the exact test; at equality the exact test "
        "runs and agrees",
    "_offset_states | lb = min(ga, gb, 0.5 * (ga - gb - abs(dz) - lipschitz * lh))":
        "equivalent: free nodes have g_b >= 0, so the mutated bound is never above the true one; more edges "
        "go to the exact test, which decides the same",
    "_search | if w_goal[k] <= dist[u]:": "equivalent: only a node linked to the goal twice at the same cost "
        "differs, and it is queued once either way",
    "_search | if key[v] > best:":
        "equivalent: at a tie the node settled next cannot lead to a cheaper start (keys never fall below "
        "the cost of a path through them)",
    "_search | pos[v] = 2": "equivalent: a settled node is never improved again (consistent keys), so its "
        "marker only spares needless relaxations",
    "_search | pos[v] = -3": "equivalent: a settled node is never improved again (consistent keys), so "
        "marking it -3 instead of -2 only costs needless relaxations",
    "_search | if size >= 0:": "equivalent: with the heap empty the entry moved to the root is the settled "
        "node itself; un-marking it is harmless, as it is never improved",
    "_search | key[u] = dist[u] - _heuristic(u, ny, nz, origin, steps, start, c_min)":
        "**not killed**: A*'s initial keys of the goal's links lowered by the heuristic; they are then popped "
        "first, which in the test lattices still relaxes each through its neighbours before it is settled",
    "_offset_states | sure = lb > min_alt": "equivalent: the shortcut only decides which edges skip the exact "
        "test; at equality the exact test runs and agrees",
    "_offset_states | state[u] = 2 if sure else 2": "equivalent: every edge goes to the exact test, which "
        "decides the same (the shortcut only saves time)",
    "edge_states | _offset_states(free, altitude, obstacle, off, 1.5 * float(np.linalg.norm(d)), float(d[2]), "
    "float(np.hypot(d[0], d[1])), terrain.max_slope if terrain is not None else 0.0, world.margins.min_altitude, "
    "has_terrain, state)": "equivalent: a stricter obstacle shortcut sends more edges to the exact test, which "
        "decides the same",
    "edge_states | _offset_states(free, altitude, obstacle, off, 0.5 * float(np.linalg.norm(d)), float(d[2]), "
    "float(np.hypot(d[0], d[1])), terrain.max_slope if terrain is not None else 1.0, world.margins.min_altitude, "
    "has_terrain, state)": "equivalent: without terrain the slope is never read (has_terrain is False)",
    # grid: A*'s box of the start's links
    "_search | if c_min > 0.0 or box[0] <= i <= box[1] or box[2] <= j <= box[3] or (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min >= 0.0 and box[0] <= i <= box[1] and (box[2] <= j <= box[3]) and (box[4] <= k <= box[5]):":
        _BOX,
    "_search | if c_min > 0.0 and box[0] < i <= box[1] and (box[2] <= j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i < box[1] and (box[2] <= j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[1] <= i <= box[1] and (box[2] <= j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[2] and (box[2] <= j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] < j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] <= j < box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[3] <= j <= box[3]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] <= j <= box[4]) and (box[4] <= k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] <= j <= box[3]) and (box[4] < k <= box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] <= j <= box[3]) and (box[4] <= k < box[5]):": _BOX,
    "_search | if c_min > 0.0 and box[0] <= i <= box[1] and (box[2] <= j <= box[3]) and (box[5] <= k <= box[5]):": _BOX,
    "pop | pos[heap[0]] = 1": "equivalent: _sift_down always sets the position of the node it sifts",
    "edge_states | for c0 in range(0, unsure.size, 200001):": "equivalent: the chunk size of the exact test",
    "edge_states | u = unsure[c0:c0 + 200001]": "equivalent: overlapping chunks test some edges twice",
    "edge_states | state[u] = world.segments_free(seg, moving=True, ends_free=True)":
        "**not killed** (conservative): a moving obstacle's position at t = 0 would block the unsure edges "
        "through it; no oracle parks a mover across an unsure edge",
    "edge_states | state[u] = world.segments_free(seg, moving=False, ends_free=False)":
        "equivalent: both ends are free nodes, so the convex end-point tests pass",
    "_edge_weight | return max(w_length * ds + w_energy * units, 1.000000000001)":
        "**not killed**: an edge cheaper than 1 would be costed 1; every test lattice's edges cost more",
    "_sift_up | if key[heap[parent]] < key[node]:": "equivalent: only the order of equal keys changes",
    "_sift_down | if c + 1 < size and key[heap[c + 1]] <= key[heap[c]]:":
        "equivalent: only the order of equal keys changes",
    "_sift_down | if key[heap[c]] > key[node]:": "equivalent: only the order of equal keys changes",
    "_heuristic | if c_min < 0.0:": "equivalent: with c_min = 0 the heuristic c_min |x - start| is 0 anyway",
    "_heuristic | if c_min > 0.0:": "equivalent in outcome: a zero heuristic makes A* Dijkstra with the same "
        "stop rule (same costs, more nodes settled)",
    # grid: the A* heuristic, the start links, the search's set-up
    "_heuristic | if c_min <= 1.0:":
        _HEUR,
    "_heuristic | k = u / nz":
        _HEUR,
    "_heuristic | j = u // nz / ny":
        _HEUR,
    "_heuristic | j = u / nz % ny":
        _HEUR,
    "_heuristic | i = u / (nz * ny)":
        _HEUR,
    "_heuristic | dx = origin[0] + i * steps[0] + start[0]":
        _HEUR,
    "_heuristic | dx = origin[0] - i * steps[0] - start[0]":
        _HEUR,
    "_heuristic | dx = origin[1] + i * steps[0] - start[0]":
        _HEUR,
    "_heuristic | dx = origin[0] + i / steps[0] - start[0]":
        _HEUR,
    "_heuristic | dx = origin[0] + i * steps[1] - start[0]":
        _HEUR,
    "_heuristic | dx = origin[0] + i * steps[0] - start[1]":
        _HEUR,
    "_heuristic | dy = origin[1] + j * steps[1] + start[1]":
        _HEUR,
    "_heuristic | dy = origin[1] - j * steps[1] - start[1]":
        _HEUR,
    "_heuristic | dy = origin[2] + j * steps[1] - start[1]":
        _HEUR,
    "_heuristic | dy = origin[1] + j / steps[1] - start[1]":
        _HEUR,
    "_heuristic | dy = origin[1] + j * steps[2] - start[1]":
        _HEUR,
    "_heuristic | dy = origin[1] + j * steps[1] - start[2]":
        _HEUR,
    "_heuristic | dz = origin[2] + k * steps[2] + start[2]":
        _HEUR,
    "_heuristic | dz = origin[2] - k * steps[2] - start[2]":
        _HEUR,
    "_heuristic | dz = origin[2] + k / steps[2] - start[2]":
        _HEUR,
    "_search | if start_near[m] != v:":
        _STARTLINK,
    "_search | best = min(best, dist[v] - w_start[m])":
        _STARTLINK,
    "_search | if pos[u] == -3 or not bits[u] >> s & 1:":
        "equivalent: a settled node is never improved again (consistent keys), so relaxing it again changes nothing",
    "_search | if alt <= dist[u]:":
        "equivalent: an equal-cost relaxation only re-queues a node at the same key",
    "_search | key[u] = alt - _heuristic(u, ny, nz, origin, steps, start, c_min)":
        _HEUR,
    "search | astar = start is not None or start_near is not None or c_min > 0.0":
        "equivalent in use: search is always called with all three of start, start_near and c_min > 0, or none",
    "search | astar = start is not None and start_near is not None and (c_min >= 0.0)":
        "equivalent: with c_min = 0 the kernel gets c_min = 0, so the start links are never checked (the "
        "stop rule never fires) and the heuristic is 0: the keys equal the costs, a full Dijkstra "
        "(test_lattice_astar_finds_each_starts_dijkstra_cost_on_an_obstacle_lattice checks it)",
    "search | key = np.full(n + 2, np.inf) if astar else dist":
        "equivalent: one spare entry, never read",
    "search | sn, ws = start_near if astar or start_near is not None else (np.zeros(0, np.int64), np.zeros(0))":
        "equivalent: the start links are read only in A* mode (c_min > 0), where they are the given ones",
    "search | sn, ws = start_near if astar and start_near is not None else (np.zeros(1, np.int64), np.zeros(0))":
        "equivalent: the start links are read only in A* mode (c_min > 0), where they are the given ones",
    "search | sn, ws = start_near if astar and start_near is not None else (np.zeros(0, np.int64), np.zeros(1))":
        "equivalent: the start links are read only in A* mode (c_min > 0), where they are the given ones",
    "search | box = np.zeros(7, dtype=np.int64)":
        "equivalent: one spare entry, never read",
    "search | if astar or sn.size:":
        "equivalent: the start links are read only in A* mode (c_min > 0), where they are the given ones",
    "search | box = np.stack([ijk.min(axis=1), ijk.min(axis=1)], axis=1).reshape(-1)":
        _STARTLINK,
    # world
    "Ellipsoid._foot_point | p = np.maximum(p, 1e-10 / a)":
        "equivalent to 1e-9 m: only the size of the nudge off a zero coordinate changes",
    "Ellipsoid._foot_point | hi = np.where(outside, a.max() * np.linalg.norm(p, axis=1), 0.0)":
        "equivalent: the points are (N, 3) here, axis 1 is axis -1",
    "Ellipsoid._foot_point | hi = np.where(outside, a.max() * np.linalg.norm(p, axis=-1), 1.0)":
        "equivalent: a wider bracket for inside points still holds the root; 64 halvings reach float resolution",
    "Ellipsoid.distance | inside = ((flat / np.asarray(self.semi_axes)) ** 2).sum(axis=1) < 1.0":
        "equivalent: flat is (N, 3), axis 1 is axis -1",
    "Ellipsoid.distance | return np.where(inside, -d, d).reshape(pb.shape[:1])":
        "not killed: differs only for batched (M, K, 3) query points, which no caller passes to an ellipsoid",
    "Ellipsoid.segments_hit | if margin < 0:":
        "equivalent: with margin 0 the scaled test finds no 'near' segment beyond 'touch'",
    "Ellipsoid.segments_hit | near = (point_segment_distance(np.zeros(3), a / scale, b / scale) < 2.0) & ~touch":
        "equivalent: more segments go through the exact golden-section test, which decides the same",
    "Ellipsoid._segment_min_distance | t1, t2 = (hi - g * (hi - lo), lo + g * (hi + lo))":
        "equivalent: lo = 0 at that point, so hi + lo = hi - lo",
    "Ellipsoid._segment_min_distance | left = f1 <= f2": "equivalent: a tie keeps the minimum in either half",
    "Ellipsoid._segment_min_distance | ends = np.minimum(self.distance(seg[:, 1]), self.distance(seg[:, 1]))":
        "equivalent to 1e-9 of the length: the golden section already converges onto the start when the minimum "
        "is there",
    "World.segments_free | if self.land is not None and ok.all():":
        "equivalent: land is burnt into the seabed (raised above the surface in every cell touching it), so "
        "the terrain's exact test already rejects every segment crossing land; the polygon test never "
        "changes the answer",
    "World.segments_free | flat = np.array(ok, dtype=bool).reshape(-2)": _NEG,
    "World.segments_free | flat[idx] = ~self.land.segments_hit(s.reshape(-2, 2, 3)[idx])": _NEG,
    "World.path_free | return bool(self.is_free(p, t, moving).any())":
        "equivalent: reached with a single point only, where any = all",
    "Ellipsoid._foot_point | sign = np.where(pb <= 0, -1.0, 1.0)":
        "equivalent to 1e-10 of the semi-axis: a zero coordinate is nudged to 1e-10 a, its sign only puts "
        "the foot point's tiny coordinate on one side of zero or the other",
    "Ellipsoid._foot_point | s2 = ((p / a) ** 2).sum(axis=1)":
        "equivalent: the points are (N, 3) here, axis 1 is axis -1",
    "Ellipsoid._foot_point | outside = s2 > 1.0":
        "equivalent: on the surface (s2 = 1) the root is t = 0, an end of either bracket",
    "Ellipsoid._foot_point | for _ in range(65):":
        "equivalent: a 65th halving moves t by 2^-65 of the bracket, below float resolution",
    "Ellipsoid._foot_point | f = ((a * p / (a2 + mid[:, None])) ** 2).sum(axis=1) - 1.0":
        "equivalent: the points are (N, 3) here, axis 1 is axis -1",
    "Ellipsoid._foot_point | pos = f >= 0": "equivalent: f = 0 means mid is the root, which either half keeps",
    "Ellipsoid.distance | flat = pb.reshape(-2, 3)": _NEG,
    "Ellipsoid.distance | d = np.linalg.norm(flat - q, axis=1)": "equivalent: flat is (N, 3), axis 1 is axis -1",
    "Ellipsoid.distance | inside = ((flat / np.asarray(self.semi_axes)) ** 2).sum(axis=-1) <= 1.0":
        "equivalent: on the surface the distance is 0, whose sign does not matter",
    "Ellipsoid.segments_hit | scale = 2.0 + margin / min(self.semi_axes)":
        "equivalent: a larger prefilter ellipsoid sends more segments to the exact test, which decides the same",
    "Ellipsoid.segments_hit | near = (point_segment_distance(np.zeros(3), a / scale, b / scale) <= 1.0) & ~touch":
        "equivalent: a segment tangent to the prefilter also goes to the exact test, which decides the same",
    "Ellipsoid.segments_hit | hit[near] = self._segment_min_distance(s[near]) <= margin":
        "boundary: a segment whose least distance is exactly the margin (the golden section's minimum is "
        "exact to 1e-9 of the length only)",
    "Ellipsoid._segment_min_distance | t1, t2 = (hi - g / (hi - lo), lo + g * (hi - lo))":
        "equivalent: hi - lo = 1 at that point",
    "Ellipsoid._segment_min_distance | t1, t2 = (hi - g * (hi + lo), lo + g * (hi - lo))":
        "equivalent: lo = 0 at that point, so hi + lo = hi - lo",
    "Ellipsoid._segment_min_distance | t1, t2 = (hi - g * (hi - lo), lo + g / (hi - lo))":
        "equivalent: hi - lo = 1 at that point",
    "Ellipsoid._segment_min_distance | for _ in range(45):":
        "equivalent: the bracket is already below 1e-9 of the length after 44 steps",
    "Ellipsoid._segment_min_distance | ends = np.maximum(self.distance(seg[:, 0]), self.distance(seg[:, 1]))":
        "equivalent to 1e-9 of the length: the golden section converges onto an end when the minimum is there, "
        "so the end values only refine it",
    "Ellipsoid._segment_min_distance | least: FloatArray = np.minimum(np.maximum(f1, f2), ends)":
        "equivalent to 1e-9 of the length: after 44 steps f1 and f2 are the distance at points 1e-9 of the "
        "length apart",
    # sim
    "_distance | if bound >= far:":
        "equivalent in the events: differs only at exactly 60 m from an obstacle, in the recorded distance",
    # local
    "key_waypoints | p = as_points(points).reshape(-2, 3)": _NEG,
    "key_waypoints | return np.ones(n - i + 1, dtype=bool)": _ONES,
    "key_waypoints | return np.ones(n + i - 1, dtype=bool)": _ONES,
    "key_waypoints | return np.ones(n - i - 2, dtype=bool)": _ONES,
    "key_waypoints | if i > n - 1:": _LAST,
    "key_waypoints | if i >= n + 1:": _LAST,
    "key_waypoints | if i >= n - 2:":
        "equivalent for a free path (the caller's plan): the penultimate point's segment to the last one is a "
        "segment of the path itself",
    "key_waypoints | continue": _LAST,
    "apf_force | d = np.asarray(distances, dtype=float).reshape(-2)": _NEG,
    "apf_force | near = d < params.radius": "equivalent: at d = r the repulsion k (1/d - 1/r) ... is 0",
    "LocalAvoidance._apf_command | centers = np.array([o[4] for o in near]).reshape(-2, 3)": _NEG,
    "LocalAvoidance._advance_goal | occupied = self.world.clearances(here, t)['moving'] <= 0.0":
        "boundary: a key waypoint exactly on a moving obstacle's margin",
    "LocalAvoidance._advance_goal | behind = np.dot(self.keys[k] - p, self.keys[min(k + 1, len(self.keys) + 1)] - "
    "self.keys[k]) < 0": "equivalent: inside the loop k < len - 1, so min(k + 1, ...) is k + 1 either way",
    "LocalAvoidance._apf_command | if alt <= 2.0 * self.params.arrive:":
        "boundary: at exactly 2 x arrive above the margin the floor is 0°; differs only there",
    "_crossings | if kb >= ka:":
        "equivalent: with kb = ka the first crossing comes after the last one, i.e. none, as in the "
        "no-movement branch",
    # the search's tail (run by the lead at the end of the session)
    'search | box = np.stack([ijk.min(axis=1), ijk.max(axis=1)], axis=1).reshape(-2)':
        _NEG,
    'search | w = cost if cost is not None else (2.0, 0.0, 1.0, 0.0, False)':
        _UNUSED_W,
    'search | w = cost if cost is not None else (1.0, 1.0, 1.0, 0.0, False)':
        _UNUSED_W,
    'search | w = cost if cost is not None else (1.0, 0.0, 2.0, 0.0, False)':
        _UNUSED_W,
    'search | w = cost if cost is not None else (1.0, 0.0, 1.0, 1.0, False)':
        _UNUSED_W,
    'search | w = cost if cost is not None else (1.0, 0.0, 1.0, 0.0, True)':
        _UNUSED_W,
    'search | settled = _search(np.array(shape, dtype=np.int64), bits, OFFSETS, vec, current, cost is not'
    ' None, float(w[0]), float(w[1]), float(w[2]), float(w[3]), bool(w[4]), np.asarray(goal_near[0], '
    'dtype=np.int64), np.asarray(goal_near[1], dtype=float), n, dist, nxt, key, np.asarray(origin, '
    'dtype=float), np.asarray(steps, dtype=float), np.zeros(4) if start is None else np.asarray(start, '
    'float), float(c_min) if astar else 0.0, np.asarray(sn, dtype=np.int64), np.asarray(ws, dtype=float),'
    ' box, np.empty(n, dtype=np.int32), np.full(n, -1, dtype=np.int32))':
        ("equivalent: without a start the search is Dijkstra (c_min = 0), whose heuristic returns 0 before "
         "reading the start point"),
    'GridReference._connect | ok = self.world.segments_free(np.stack([p, q], axis=1), moving=True)':
        ("**not killed** (conservative): a moving obstacle's position at t = 0 would block links of the start "
        "or goal to the lattice; no oracle parks a mover across such a link"),
    # cost, every mutant (lead, end of session)
    "_path_terms | g_p = pz + elevation_kernel(coef, x0, y0, dx, dy, px, py) if has_terrain else math.inf":
        "equivalent for points at or below the surface: only the first segment's start altitude changes, and "
        "the shortcut's bound is at most min(g_a', g_b) and 0.5 (g_a' + g_b - |dz| - G L) <= 0.5 (g_a' + g_a) "
        "= pz <= 0 when the true minimum is below the threshold (Lipschitz), so the exact walk still runs",
    "_obstacle_slack | slack = np.minimum(slack, np.where(hit, np.minimum(d - m.obstacle, -1.0), d + m.obstacle))":
        "equivalent: that branch is taken where the segment keeps the margin (d >= margin), where d - margin "
        "and d + margin are both >= 0: neither is charged",
    # cost, the full run's remaining survivors (lead, end of session)
    '_obstacle_slack | touch = shape.segments_hit(ends, 1.0)':
        ('not killed (reporting, conservative): a segment passing within 1 m of an obstacle without touching '
         'would report clearance 0 (and with a zero margin count as a violation); no test passes that close'),
    '_obstacle_slack | hit = shape.segments_hit(ends, m.obstacle) if m.obstacle >= 0 else touch':
        ('equivalent: with a zero margin segments_hit(ends, 0) is touch'),
    '_obstacle_slack | hit = shape.segments_hit(ends, m.obstacle) if m.obstacle > 1 else touch':
        ('**not killed**: a margin of at most 1 m would be ignored (touch used instead); the tests use margins'
         ' of 0 or >= 5 m'),
    '_obstacle_slack | clearance = np.minimum(clearance, np.where(touch, np.minimum(d, 1.0), d))':
        ('not killed (reporting only): a touching segment whose ends are over 1 m away would report clearance '
         '1 m instead of 0; violations are unaffected'),
    'segment_energy | a, b, *given = (np.ascontiguousarray(np.broadcast_to(v, lead + (3,)).reshape(-2, '
    '3)) for v in arrays)': _NEG,
    'energy_kernel | c_par = (cx * ex + cy * ey + cz * ez) / ds if ds > 0.0 else 1.0':
        ('equivalent: with ds = 0 the time, the energy and the blocked flag are all 0 / False whatever c_par'),
    'energy_kernel | blocked = (disc <= 0.0 or vg <= 1e-09) and ds > 0.0':
        ('boundary: differs only when the cross current equals the speed exactly'),
    'energy_kernel | blocked = (disc < 0.0 or vg < 1e-09) and ds > 0.0':
        ('boundary: differs only at a ground speed of exactly 1e-9 m/s'),
    'energy_kernel | blocked = (disc < 0.0 or vg <= 1e-09) and ds >= 0.0':
        ('not killed: a zero-length leg in a current faster than the vehicle would count as blocked (one more '
         'violation); no test has one'),
    'energy_kernel | blocked = (disc < 0.0 or vg <= 1e-09) and ds > 1.0':
        ("**not killed**: legs shorter than 1 m would never count as blocked; the tests' blocked legs are "
         'longer'),
    'energy_kernel | t = ds / (speed if blocked or vg < 0.0 else vg) if ds > 0.0 else 0.0':
        ('equivalent: at vg = 0 with ds > 0 the leg is blocked (vg <= 1e-9), so the speed is used either way'),
    'evaluate_paths | other_slack = other_clear = np.empty((1, 0))':
        ('equivalent: without obstacles the kernel is told has_other = False and never reads these arrays'),
    'evaluate_paths | other_slack = other_clear = np.empty((0, 1))':
        ('equivalent: without obstacles the kernel is told has_other = False and never reads these arrays'),
    # mission (issue #31)
    'leg_floors | a, b = (as_points(a).reshape(-2, 3), as_points(b).reshape(-1, 3))':
        _NEG,
    'leg_floors | a, b = (as_points(a).reshape(-1, 3), as_points(b).reshape(-2, 3))':
        _NEG,
    'envelope_hits | a, b = (as_points(a).reshape(-2, 3), as_points(b).reshape(-1, 3))':
        _NEG,
    'envelope_hits | a, b = (as_points(a).reshape(-1, 3), as_points(b).reshape(-2, 3))':
        _NEG,
    'envelopes_free | a, b = (as_points(a).reshape(-2, 3), as_points(b).reshape(-1, 3))':
        _NEG,
    'envelopes_free | a, b = (as_points(a).reshape(-1, 3), as_points(b).reshape(-2, 3))':
        _NEG,
    '_sampled_rect_distance | out[k] = float(shape.distance(pts.reshape(-2, 3)).min())':
        _NEG,
    'held_track | w = as_points(waypoints).reshape(-2, 3)':
        _NEG,
    'fly_check | w = as_points(waypoints).reshape(-2, 3)':
        _NEG,
    'waypoint_limits | w = as_points(waypoints).reshape(-2, 3)':
        _NEG,
    '_parallelogram_distance | a11 = (e1 * e1).sum(1)':
        _AXIS,
    '_parallelogram_distance | a22 = (e2 * e2).sum(1)':
        _AXIS,
    '_parallelogram_distance | a12 = (e1 * e2).sum(1)':
        _AXIS,
    '_parallelogram_distance | r1, r2 = (-(o * e1).sum(1), -(o * e2).sum(-1))':
        _AXIS,
    '_parallelogram_distance | r1, r2 = (-(o * e1).sum(-1), -(o * e2).sum(1))':
        _AXIS,
    '_parallelogram_distance | plane = np.linalg.norm(o + s[:, None] * e1 + t[:, None] * e2, axis=1)':
        _AXIS,
    'envelopes_free | ok: NDArray[np.bool_] = np.all((-ends[..., 2] >= m.min_depth) & (-ends[..., 2] <= m'
    '.max_depth), axis=1)':
        _AXIS,
    'envelopes_free | ok &= world.bounds.contains(ends).all(axis=1)':
        _AXIS,
    'fly_check | near = point_segment_distance(np.asarray(shape.center), o, o + e1) - shape.bounding_radi'
    'us < 200.0 + np.linalg.norm(e2, axis=1)':
        _AXIS,
    '_parallelogram_distance | safe = np.where(ok, det, 2.0)':
        _UNUSED_SAFE,
    '_parallelogram_distance | inside = ok & (s > 0) & (s <= 1) & (t >= 0) & (t <= 1)':
        _ON_EDGE,
    '_parallelogram_distance | inside = ok & (s >= 0) & (s < 1) & (t >= 0) & (t <= 1)':
        _ON_EDGE,
    '_parallelogram_distance | inside = ok & (s >= 0) & (s <= 1) & (t > 0) & (t <= 1)':
        _ON_EDGE,
    '_parallelogram_distance | inside = ok & (s >= 0) & (s <= 1) & (t >= 0) & (t < 1)':
        _ON_EDGE,
    'fly_check | k = int(np.argmin(alt)) if np.isfinite(alt).all() else -1':
        'equivalent: alt is all finite (a seabed) or all inf (none), so any() is all()',
    'held_track | if 0.0 < need <= length:':
        ('equivalent: at need = length the depth change ends exactly at the waypoint either way; the mutant ad'
         'ds the same point twice (a zero-length segment)'),
    'envelope_hits | return _parallelogram_distance(uo, ue1, ue2) <= 1.0':
        'boundary: an envelope exactly on the inflated surface (distance exactly the margin)',
    'MissionCheck.ok | return alt > self.required_altitude_m - 1e-06 and self.obstacle_hits == 0 and (sel'
    'f.executor_obstacle_hits == 0) and (self.limits is None or self.limits.ok)':
        'boundary: an altitude of exactly required - 1e-6 m',
    'fly_check | near = point_segment_distance(np.asarray(shape.center), o, o + e1) - shape.bounding_radi'
    'us <= 200.0 + np.linalg.norm(e2, axis=-1)':
        "boundary: an obstacle surface exactly 200 m (plus the envelope's height) from a leg",

    '_parallelogram_distance | ok = det > 1e-12 * np.minimum(a11 * a22, 1e-300)':
        ("equivalent to 1e-6 of the leg: with the guard at det > 1e-312 the plane's solution is also taken whe"
         "re det <= 1e-12 a11 a22; an envelope's edges are orthogonal before the obstacle's affine map, so tha"
         "t needs a depth change under 1e-6 of the leg (or ellipsoid axes 1e6 apart), where the plane's and th"
         "e edges' distances differ by less than that height"),
    '_sampled_rect_distance | nt = int(np.clip(np.ceil(np.linalg.norm(e2[k]) / step), 1, 500)) + 1':
        ('equivalent: with e2 = 0 (a level leg) the extra row repeats the same points; otherwise ceil(h / step'
         ') >= 1 already'),
    '_sampled_rect_distance | ns = int(np.clip(np.ceil(np.linalg.norm(e1[k]) / step), 2, 2000)) + 1':
        ('not killed (reporting precision): a finer grid for the reported ellipsoid distance, only closer to t'
         'he exact value (the 0.25 m grid is within 0.005 m of it in the tests); the verdict uses the exact en'
         'velope test'),
    '_sampled_rect_distance | ns = int(np.clip(np.ceil(np.linalg.norm(e1[k]) / step), 1, 2001)) + 1':
        ('not killed (reporting precision): a finer grid for the reported ellipsoid distance, only closer to t'
         'he exact value (the 0.25 m grid is within 0.005 m of it in the tests); the verdict uses the exact en'
         'velope test'),
    '_sampled_rect_distance | ns = int(np.clip(np.ceil(np.linalg.norm(e1[k]) / step), 1, 2000)) + 2':
        ('not killed (reporting precision): a finer grid for the reported ellipsoid distance, only closer to t'
         'he exact value (the 0.25 m grid is within 0.005 m of it in the tests); the verdict uses the exact en'
         'velope test'),
    '_sampled_rect_distance | nt = int(np.clip(np.ceil(np.linalg.norm(e2[k]) / step), 0, 501)) + 1':
        ('not killed (reporting precision): a finer grid for the reported ellipsoid distance, only closer to t'
         'he exact value (the 0.25 m grid is within 0.005 m of it in the tests); the verdict uses the exact en'
         'velope test'),
    '_sampled_rect_distance | nt = int(np.clip(np.ceil(np.linalg.norm(e2[k]) / step), 0, 500)) + 2':
        ('not killed (reporting precision): a finer grid for the reported ellipsoid distance, only closer to t'
         'he exact value (the 0.25 m grid is within 0.005 m of it in the tests); the verdict uses the exact en'
         'velope test'),

    # sim (issue #31 run)
    '_obstacle_shapes | if centres is not None:':
        ("equivalent in use: both callers (sim.loop, sim_formation) pass the moving obstacles' centres at t fr"
         'om their motions (the precomputed tracks), which the mutant recomputes with o.center(t)'),

}

# issue #49: the new modules' survivors, argued
_UNIFORM = ("equivalent: a Terrain's axes are uniform (Terrain.__post_init__ rejects steps that differ by more than "
            "1e-6 relative), so the largest and the least step of an axis are the same")
REASONS.update({
    "slope_sigma | h = max(float(np.min(np.diff(x))), float(np.max(np.diff(y))))": _UNIFORM,
    "slope_sigma | h = max(float(np.max(np.diff(x))), float(np.min(np.diff(y))))": _UNIFORM,
    "IncrementalBudget.run | p = np.asarray(waypoints, dtype=float).reshape(-2, 3)": _NEG,
    "IncrementalBudget.run | tr = traverse(self.world, p[i:i + 3], v[i], 0.0, self.ds)":
        ("equivalent: the time at the leg's end is times[1] whether the flight goes on one more leg or not; a "
         "blocked extra leg falls back to the whole flight, which is the same budget"),
    "IncrementalBudget.run | s = np.concatenate([[1.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])":
        ("equivalent in use: node_s of the cached budget's Traverse is read by Traverse.at only (the point of no "
         "return), which serve never asks of it; budget_of and charge() do not read it"),
    "IncrementalBudget.run | s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=1), axis=1))])":
        ("equivalent in use: node_s of the cached budget's Traverse is read by Traverse.at only (the point of no "
         "return), which serve never asks of it; budget_of and charge() do not read it"),
    ("IncrementalBudget.run | tr = Traverse(p, v, times, p.copy(), s, times.copy(), "
     "np.r_[1, np.arange(n)].astype(np.int64))"):
        ("equivalent: node_leg[0] (the first node's leg) is never read: charge() multiplies power[legs][1:] by the "
         "time steps"),
    "_finish | if status is Status.EXACT and energy >= model.budget_wh:":
        ("boundary, not killed: a flight that uses exactly its budget keeps exactly its reserve (EXACT); the mutant "
         "calls it RESERVE_BROKEN, which no float example hits"),
})

# issue #49, second session: vehicle-limits' survivors, argued (the rest killed by tests/unit/test_limits_by_hand.py)
_HYPOT3 = ("equivalent: np.hypot(dx, dy, dz) passes dz as hypot's ``out`` array, so the values are hypot(dx, dy) "
           "all the same")
_SCALE = "equivalent: atan2(|a x b|, a . b) does not change when a or b is scaled by a positive length"
_AT_TOL = ("boundary, not killed: the figure would have to equal the limit + 1e-9 (or R (1 - 1e-9)) exactly; at the "
           "limit itself the check passes either way (test_check_limits_at_exactly_each_limit_passes)")
REASONS.update({
    "turn_angles | prev = -2": "equivalent: prev only tells whether a previous leg exists (prev >= 0)",
    "turn_angles | for k in np.flatnonzero(length >= MIN_LEG_M):":
        "boundary, not killed: a leg exactly 1e-6 m long (MIN_LEG_M) counts as a leg; no mission has one",
    "turn_angles | a, b = (d[prev] * length[prev], d[k] / length[k])": _SCALE,
    "turn_angles | a, b = (d[prev] / length[prev], d[k] * length[k])": _SCALE,
    "leg_turn_radius | length = np.hypot(*np.diff(p[:, :3], axis=0).T)": _HYPOT3,
    "leg_turn_radius | half = np.tan(np.minimum(turn_angles(p), math.pi + 1e-12) / 2.0)":
        ("equivalent in use: only a reversal (pi) tells; its fit radius is then L / 1.6e16 instead of L / 2e12, "
         "below a micrometre either way, so every limit reads it as 0"),
    "leg_turn_radius | half = np.tan(np.minimum(turn_angles(p), math.pi - 1.000000000001) / 2.0)":
        ("not killed: turns over pi - 1 rad (123 deg) read as 123 deg, their fit radius 1.7x too large; "
         "a turn that tight fails R anyway unless its legs are long (no test has one)"),
    "leg_turn_radius | r = np.where(need >= 1e-15, length / np.where(need > 1e-15, need, 1.0), np.inf)":
        "boundary: need exactly 1e-15 (turns of 2e-15 rad), where L / need is 1e15 m: no limit tells",
    "leg_turn_radius | r = np.where(need > 1e-15, length / np.where(need >= 1e-15, need, 1.0), np.inf)":
        "equivalent: the inner guard only keeps the discarded branch finite",
    "leg_turn_radius | r = np.where(need > 1e-15, length / np.where(need > 1e-15, need, 2.0), np.inf)":
        "equivalent: the placeholder divisor's result is discarded by the outer np.where",
    "check_limits | if pitch[k] >= limits.max_pitch_deg + tol:": _AT_TOL,
    "check_limits | if depth[k] >= limits.max_depth_m + tol:": _AT_TOL,
    ("check_limits | bad += [LimitViolation(int(turns[k]), 'turn_radius_m', float(radius[k]), limits.turn_radius_m) "
     "for k in np.flatnonzero(radius <= limits.turn_radius_m * (1.0 - tol))]"): _AT_TOL,
    "corner_indices | kept = np.asarray(line.simplify(tolerance, preserve_topology=True).coords)[:, 2]":
        ("equivalent in use: a track's simplification keeps the same vertices with or without topology "
         "preservation unless the simplified track would cross itself (a self-crossing at the tolerance's scale)"),
    "corner_indices | return np.unique(np.r_[1, np.rint(kept).astype(np.intp), len(p) - 1])":
        ("not killed (conservative): index 0 is always kept by Douglas-Peucker; the mutant also keeps vertex 1, a "
         "corner within the tolerance of the track, which can only add a turn to check (a stricter verdict)"),
    "flyby_arcs | if dpsi[i] <= 1e-12:": "boundary: a turn of exactly 1e-12 rad (its arc is 1e-12 R long)",
    "flyby_arcs | side = 1.0 if u[0] * v[1] - u[1] * v[0] >= 0 else -1.0":
        "boundary: cross = 0 with a turn is a reversal (pi), whose fly-by does not exist (fit radius 0, flagged)",
    "repair_pitch | s = np.r_[1.0, np.cumsum(np.hypot(*np.diff(p[:, :2], axis=0).T))]":
        "equivalent: the profile depends on distances between vertices only (s shifted by 1 m everywhere)",
    "repair_pitch | s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p[:, :3], axis=0).T))]": _HYPOT3,
    ("repair_pitch | slope = math.tan(math.radians(max(max_pitch_deg - PITCH_SLACK_DEG, 0.5 / max_pitch_deg)))"):
        "boundary: differs only for pitch limits under 0.72 deg (0.5 / limit > limit - 0.05); none is flown",
})
REASONS.update({
    ("check_limits | return LimitReport(0.0, -1, math.inf, -1, float(-full[:, 2].max()) if len(full) else 0.0, (), "
     "limits)"): "equivalent: the branch holds one point at most, whose least and largest z are the same",
    ("check_limits | return LimitReport(0.0, -1, math.inf, -1, float(-full[:, 2].min()) if len(full) else 1.0, (), "
     "limits)"):
        "equivalent in use: an empty polyline's depth; every caller passes two points or more (plans, missions)",
    "corner_indices | if tolerance <= 0.0 and len(p) < 3:":
        ("equivalent in use: tolerance 0 comes from turn_radius_m = 0, when no turn is checked; Douglas-Peucker at 0 "
         "only drops exactly collinear vertices (the reported tightest turn of an unlimited vehicle may change)"),
    "corner_indices | if tolerance < 0.0 or len(p) < 3:":
        ("equivalent in use: tolerance 0 comes from turn_radius_m = 0, when no turn is checked; Douglas-Peucker at 0 "
         "only drops exactly collinear vertices (the reported tightest turn of an unlimited vehicle may change)"),
    "corner_indices | if tolerance <= 1.0 or len(p) < 3:":
        ("not killed (conservative): radii up to 10 m (track tolerance 0.1 R <= 1 m) judge every vertex of a dense "
         "curve as a corner, a stricter verdict"),
    "merge_close | if keep[-1] != len(p) + 1:":
        ("equivalent in use: when the last kept vertex is the end the branch rewrites it with itself; only a single "
         "point becomes [0, 0], which check_limits returns before merging"),
    "enforce_limits | if lim is None or not result.status.ok or result.path.shape[1] < 2:":
        ("equivalent: shape[1] is 3; a path of 0 or 1 point then reaches check_limits, whose report is ok, and is "
         "returned unchanged as before"),
    "enforce_limits | steep = all((v.limit == 'max_pitch_deg' for v in report.violations))":
        ("not killed (message only): with pitch and turn violations both verdicts are INFEASIBLE (a repair keeps the "
         "horizontal track, so the turn stays); the original names what is left after the pitch repair"),
})

# issue #49, second session: endurance's survivors (a seeded sample of 40), argued
REASONS.update({
    "budget_of | ground = np.where(moving >= 0, length / np.where(moving > 0, moving, 1.0), np.nan)":
        ("reporting only: a leg with no moving time (a pure dwell) reports ground speed length / 1 = 0 m/s instead of "
         "NaN; the verdict, energies and times are the same"),
    "budget_of | if margin < -1e-09 / model.battery_wh:":
        "boundary: the float tolerance on the margin (1e-9 of the battery in Wh) at 1e-9 / battery instead",
    "budget_of | over = int(np.argmax(remaining <= model.reserve_wh - 1e-09 * model.battery_wh))":
        "boundary: which leg 'enters' the reserve when a leg ends exactly on it (within 1e-9 of the battery)",
    "_return_energy | keep = np.r_[True, np.linalg.norm(np.diff(back, axis=0), axis=1) > 1.000000001]":
        ("not killed (sub-metre): return-route vertices closer than 1 m to the previous one are dropped; the way "
         "back changes by under a metre per dropped vertex"),
    "point_of_no_return | grid = np.linspace(0.0, total, max(2, samples) + 2)":
        ("not killed (scan resolution): 42 scan points instead of 41; both find the first crossing of a hump of f "
         "wider than total / 40 (test_point_of_no_return_is_the_first_crossing_when_the_way_back_costs_more_per_metre"
         ", whose f is not monotonic); a narrower hump is found or missed by either grid depending on where its "
         "points fall, so no test can prefer one without pinning the grid"),
    "point_of_no_return | grid = np.linspace(0.0, total, max(3, samples) + 1)":
        ("equivalent in use: max(3, samples) differs from max(2, samples) only for samples <= 2; both callers "
         "(endurance.assess) pass the default 40"),
    "point_of_no_return | if f0 >= 0:":
        ("boundary: f(0) exactly 0, a return from the start to a rally point costing exactly the budget (home as the "
         "recovery gives f(0) = -budget < 0: EnergyModel requires reserve < usable)"),
    "point_of_no_return | while hi - lo >= tol:": "equivalent within tol: one more bisection step at most",
    "point_of_no_return | if fm >= 0:": "boundary: a bisection midpoint exactly at the point of no return (f = 0)",
})

# issue #49, second session: geoinput's survivors (a seeded sample of 40), argued
REASONS.update({
    ("_derive_origin | return (0.5 * (float(lat.min()) + float(lat.max())), float(np.mod(lon0 - 180.0, 360.0) - "
     "180.0))"): "equivalent: lon0 + 180 and lon0 - 180 differ by 360, which np.mod(..., 360) removes",
    ("resolve_positions | pts = [(g[0], g[1]) for _, _, _, g, mission in found if mission] or [(g[1], g[1]) for _, _, "
     "_, g, _ in found]"):
        ("not killed: the origin of a scenario whose only geographic positions lie outside [mission] (obstacles, "
         "rally points given in degrees, the mission in metres); no test has one"),
})

# issue #49, second session: survey-turns' survivors (a seeded sample of 40), argued
REASONS.update({
    "_words | if p2 > 0:": ("boundary: an LSR with no straight (p2 = 0 exactly) is then left out; the LRL/RLR or "
                            "another CSC word of the same length covers it only if one exists, which no float "
                            "configuration of the tests hits"),
    "_words | if abs(tmp) < 1:": ("boundary: a CCC word whose middle arc is exactly 2pi - acos(+-1); "
                                  "the CSC words cover these configurations"),
})

# issue #49, third session: ladder's and tail-first's survivors (every mutant run; the rest killed by
# tests/unit/test_ladder_by_hand.py and tests/unit/test_tail_by_hand.py), argued
REASONS.update({
    "plan_ladder | edges, screened, refined, won, why = (0, 0, 0, (cells[0], 1), '')":
        ("equivalent: won's first value is never read: it is read after the loop only when best is not None, and "
         "best and won are set together (a plan is won only by a refined rung, which sets both)"),
    "plan_ladder | if best is not None and cost - best_screened > MARGIN * best_screened:":
        ("equivalent: best_screened is a screened path cost (length, or the cost model's energy/time terms plus "
         "penalties), never negative, so abs(best_screened) is best_screened"),
    "read_tail | if not rows or 'tail_first' not in rows[1] or len(rows) != legs + 1:":
        ("equivalent: csv.DictReader gives every row the header's keys (short rows filled with None), so rows[1] "
         "has 'tail_first' exactly when rows[0] has; with a single row rows[1] raises IndexError, read as no flags "
         "(None), as the original's legs + 1 == 1 rows give no tail-first leg"),
    "read_tail | if math.hypot(*d) >= 1e-09:":
        "boundary: a ROS Path leg exactly 1e-9 m long (no direction to judge the pose against)",
    ("read_tail | flags[i] = math.cos(_yaw_of(poses[i]['pose']['orientation']) - math.atan2(d[1], d[0])) <= 0.0"):
        ("equivalent: the cosine of a double is never exactly 0 (no double is an odd multiple of pi/2; the nearest, "
         "fl(pi/2), gives 6.1e-17), so < 0 and <= 0 agree on every yaw"),
})

# issue #49, third session: endurance run whole (all 255) against tests/unit/test_endurance_by_hand.py; the
# survivors not argued above
_SCAN = ("not killed (scan resolution): the scan of f along the route moves or loses a point; the bisection from "
         "the last point where f <= 0 still finds the first crossing of every hump of f wider than two scan "
         "intervals (test_point_of_no_return_is_the_first_crossing_when_the_way_back_costs_more_per_metre), a "
         "narrower one is found or missed by either grid depending on where its points fall")
REASONS.update({
    "traverse | p = np.asarray(points, dtype=float).reshape(-2, 3)": _NEG,
    ("traverse | back = np.zeros(p.shape[0] - 1, dtype=bool) if tail is None else "
     "np.asarray(tail, dtype=bool).reshape(-2)"): _NEG,
    "traverse | nodes, node_s, node_t, node_leg = ([p[0]], [0.0], [depart], [1])":
        ("equivalent: the first node's leg is never read: Traverse.at returns node_leg[j] with j >= 1 (clipped), "
         "and budget_of does not read node_leg"),
    "budget_of | ground = np.where(moving > 0, length / np.where(moving >= 0, moving, 1.0), np.nan)":
        "equivalent: the inner guard only keeps the branch the outer np.where discards (moving = 0) finite",
    "budget_of | ground = np.where(moving > 0, length / np.where(moving > 0, moving, 2.0), np.nan)":
        "equivalent: the placeholder divisor's result is discarded by the outer np.where",
    "budget_of | if margin <= -1e-09 * model.battery_wh:":
        "boundary: a margin of exactly -1e-9 of the battery (Wh), the float tolerance itself",
    "_return_energy | keep = np.r_[True, np.linalg.norm(np.diff(back, axis=0), axis=1) >= 1e-09]":
        "boundary: return-route vertices exactly 1e-9 m apart",
    "point_of_no_return | grid = np.linspace(1.0, total, max(2, samples) + 1)": _SCAN,
    "point_of_no_return | grid = np.linspace(0.0, total, max(2, samples) - 1)": _SCAN,
    "point_of_no_return | for s in grid[2:]:": _SCAN,
    "point_of_no_return | lo, r_lo = (1.0, r0)":
        ("not killed (within tol): the bisection's lower end starts 1 m (the default tol) along the route; it "
         "differs only for a point of no return within the first metre"),
    "point_of_no_return | if fs >= 0:": "boundary: a scan point exactly at the point of no return (f = 0)",
})

# wave 12's safety- and verdict-deciding code (the session of 6 Dec 2026 from 17:00): validate's numpy seabed
# bound, the terrain-frame and held-depth zone checks of `mission check`, its verdicts, the survey's bridges
# round zones, and the front door's SciPy stand-ins whose results feed every seabed model
WORLD_ZONES_SEGMENTS = "auvplan.world.zones.segments"
TERRAIN_LEGS, ZONE_LEGS = "auvplan.guidance.mission.terrain_legs", "auvplan.guidance.mission.zone_legs"
APP_CHECK, JOINS = "auvplan.app.check", "auvplan.survey.joins"
BOUNDED_MIN, SEABED = "auvplan.optim.bounded_min", "auvplan.world.seabed"
MODULES.update({
    # validate's "clearly free" start and goal: the numpy seabed and its bound, the ellipsoid's lower bound
    "clearly-free": Target(
        _fns(WORLD, "World.clearly_free", "_lower_distance") + _fns(TERRAIN, "Terrain.elevation_bounds"),
    ),
    # a .plan's terrain-frame legs flown at the commanded altitude above the seabed
    "terrain-track": Target(_fns(TERRAIN_LEGS, "_pieces", "_following_leg", "_flags", "terrain_track")),
    # the zones a held-depth executor may enter: each leg's envelope and the executor's track
    "zone-legs": Target(
        _fns(ZONE_LEGS, "_track_legs", "held_zone_entries")
        + _fns(WORLD_ZONES_SEGMENTS, "SegmentQueries.envelope_entries"),
    ),
    # mission check's verdicts (ok, check_ok; the exit code is max(0 if ok else 1)), the zones' closest approach
    # and entries, the terrain-following check
    "mission-verdict": Target(
        ((APP_CHECK, "check_missions", "follow = None", "out.append(FileCheck("),)
        + _fns(APP_CHECK, "_zone_approach", "terrain_following_check"),
    ),
    # the survey's bridges round zones joined by turns, and the turn's fit-and-clear test
    "survey-joins": Target(_fns(JOINS, "_fits", "_bridge", "join_bridges")),
    # data inspect's extents (SciPy's bounded Brent, bit for bit) and the projection margin's window maximum
    "front-door": Target(
        _fns(BOUNDED_MIN, "_sign", "bounded_min") + _fns(SEABED, "_run_max", "window_max"),
    ),
})

# wave 12's targets (run 6 Dec 2026 evening): the survivors argued equivalent or float boundaries
_DUP = ("equivalent: a parameter of exactly 0 or 1 is the leg's own end, already in the list; np.unique drops the "
        "duplicate (-0.0 == 0.0)")
_FLAT = "equivalent: the placeholder of a flat piece only has to lie outside (0, 1), which -1, 1 and -2 all do"
_PARABOLA_EMPTY = ("equivalent: with q = 0 the parabola's test abs(p) < abs(0.5 q r) = 0 fails whatever p's sign, "
                   "and the golden step is taken")
_STEP = ("equivalent for xatol > 0 (the only caller passes 1e-12): a step is at least tol1 = sqrt(2.2e-16) |xf| + "
         "xatol / 3, more than half an ulp of xf, so x never equals xf")
_FLOATEQ = ("boundary: needs two computed doubles exactly equal (SciPy's own strictness); no seeded search of 12 000 "
            "cases hit it")
REASONS.update({
    "_pieces | s.append(t[(t >= 0.0) & (t < 1.0)])": _DUP,
    "_pieces | s.append(t[(t > 0.0) & (t <= 1.0)])": _DUP,
    "terrain_track | w = as_points(waypoints).reshape(-2, 3)": _NEG,
    "terrain_track | f = np.asarray(follow, dtype=bool).reshape(-2)": _NEG,
    "terrain_track | t = np.where(np.abs(q2) >= 1e-12, -q1 / (2.0 * q2), -1.0)":
        "boundary: a piece's curvature term exactly 1e-12 m; then its extremum or none, both within 1e-12 m of a chord",
    "terrain_track | t = np.where(np.abs(q2) > 1e-12, -q1 / (2.0 * q2), 1.0)": _FLAT,
    "terrain_track | t = np.where(np.abs(q2) > 1e-12, -q1 / (2.0 * q2), -2.0)": _FLAT,
    "terrain_track | inner = (t >= 0.0) & (t < 1.0)":
        "equivalent: t = 0 gives s0 + 0 (s1 - s0) = s0 exactly, a duplicate np.unique drops",
    "terrain_track | inner = (t > 0.0) & (t <= 1.0)":
        ("boundary: t exactly 1 (q1 = -2 q2 to the bit) adds s0 + (s1 - s0), s1 or an ulp from it: a vertex on the "
         "track within an ulp of another"),
    "bounded_min | rat = e = 1.0":
        ("equivalent: with e = 1 the first pass tries the parabola through three equal points (r = q = p = 0), "
         "which fails, and the golden step sets e and rat; with tol1 >= 1 no parabola is tried"),
    "bounded_min | while abs(xf - xm) >= tol2 - 0.5 * (b - a):": _FLOATEQ,
    "bounded_min | if abs(e) >= tol1:": _FLOATEQ,
    "bounded_min | if q >= 0.0:": _PARABOLA_EMPTY,
    "bounded_min | if abs(p) <= abs(0.5 * q * r) and p > q * (a - xf) and (p < q * (b - xf)):": _FLOATEQ,
    "bounded_min | rat = (p - 0.0) / q":
        ("equivalent: p - 0.0 and p + 0.0 differ only for p = -0.0, giving rat = -0.0 instead of 0.0: the same x, "
         "_sign(-0.0) = 1, the same abs(e)"),
    "bounded_min | if x - a <= tol2 or b - x < tol2:": _FLOATEQ,
    "bounded_min | if x - a < tol2 or b - x <= tol2:": _FLOATEQ,
    "bounded_min | rat = tol1 / _sign(xm - xf)": "equivalent: _sign is +1 or -1 (or NaN), so dividing is multiplying",
    "bounded_min | if x > xf:": _STEP,
    "bounded_min | if x <= xf:": _STEP,
    "_run_max | while 2 * span < width:":
        ("equivalent: stopping one doubling earlier leaves span >= width / 2, and two overlapping runs of span still "
         "cover each window of width"),
    ("_run_max | out: FloatArray = np.moveaxis(np.maximum(run[:n], run[width - span:width + span + n]), 0, "
     "axis)"): ("equivalent: the slice's end is past the run's length (width - span + n = len(run)), so it is "
                "clipped there"),
})
_ORDER = ("not killed (order of the tries): the final check of the whole bridge [head, inner, tail] tests every "
          "inner leg and corner, so a laxer or stricter pre-check of the turn in only changes which entry, exit "
          "or direct turn is tried next; no bridge of the tests tells")
REASONS.update({
    "_track_legs | legs = np.empty(track.shape[0] + 1, dtype=np.intp)":
        "equivalent: the two extra trailing entries are never read (indexed by segments < M - 1)",
    "held_zone_entries | w = as_points(waypoints).reshape(-2, 3)": _NEG,
    ("held_zone_entries | pairs = np.unique(np.concatenate([np.column_stack([legs, zi]), np.column_stack("
     "[_track_legs(w, track)[seg], tz])]), axis=0).reshape(-2, 2)"): _NEG,
    "held_zone_entries | if not zones and w.shape[0] < 2:":
        ("equivalent: with zones and one waypoint the rest gives the same empty integer arrays (no leg, a "
         "one-point track; test_one_leg_one_waypoint_and_no_zones)"),
    "held_zone_entries | if not zones or w.shape[1] < 2:":
        "equivalent: shape[1] is 3; one waypoint then runs through the rest, which gives the same empty arrays",
    ("SegmentQueries.envelope_entries | a, b = (np.asarray(a, dtype=float).reshape(-2, 3), np.asarray(b, "
     "dtype=float).reshape(-1, 3))"): _NEG,
    ("SegmentQueries.envelope_entries | a, b = (np.asarray(a, dtype=float).reshape(-1, 3), np.asarray(b, "
     "dtype=float).reshape(-2, 3))"): _NEG,
    "SegmentQueries.envelope_entries | if not self.zones and a.shape[0] == 0:":
        "equivalent: no legs query the R-tree with nothing and give the same empty intp arrays",
    "SegmentQueries.envelope_entries | if not self.zones or a.shape[1] == 0:":
        "equivalent: shape[1] is 3; no legs then query the R-tree with nothing: the same empty intp arrays",
    "terrain_following_check | return sorted({int(seg_leg[v - 1]) for v in vertices if v >= 0})":
        ("equivalent in use: fly_check(..., launch=True) exempts vertex 0 (the plan's home) from the waypoint "
         "limits, so it is never listed"),
    "_fits | tight = helm_check(whole, VehicleLimits(90.0, radius), min_leg=1.0).tightest_turn_m":
        "equivalent: min_leg only adds 'min_leg_m' violations; tightest_turn_m does not depend on it",
    "_fits | return bool(tight > radius * (1.0 - 1e-09) and world.path_free(whole[1:-1]))":
        "boundary: a turn fitting exactly R (1 - 1e-9)",
    "_fits | return bool(tight >= radius / (1.0 - 1e-09) and world.path_free(whole[1:-1]))":
        ("boundary: turn_between draws every turn until it fits R (not R - 1e-9 R); a corner between R (1 - 1e-9) "
         "and R (1 + 1e-9) would have to fit to a few parts in 1e9"),
    "_fits | return bool(tight >= radius * (1.0 + 1e-09) and world.path_free(whole[1:-1]))":
        ("boundary: turn_between draws every turn until it fits R (not R - 1e-9 R); a corner between R (1 - 1e-9) "
         "and R (1 + 1e-9) would have to fit to a few parts in 1e9"),
    "_fits | return bool(tight >= radius * (1.0 - 1e-09) and world.path_free(whole[1:-2]))":
        ("not killed: the turn in's last leg is an inner leg of the whole bridge too, whose check rejects the same "
         "bridge (test_a_sphere_on_a_turn_s_first_or_last_leg_is_kept_clear: the result is clear either way)"),
    "_bridge | for k in range(1, m - 2):":
        "equivalent: k = m - 2 has no exit to try (range(m - 2, k, -1) is empty) and breaks to the direct turn anyway",
    "_bridge | t_in, _ = turn_between(head, d[k:k + 3], radius)":
        "equivalent: turn_between reads the first two points of its second argument only",
    "_bridge | if not _fits(world, np.vstack([head, t_in, d[k:k - 2]]), radius):": _ORDER,
    "_bridge | if not _fits(world, np.vstack([head, t_in, d[k:k + 3]]), radius):": _ORDER,
    "_bridge | for j in range(m - 2, k, -2):": _ORDER,
    "_bridge | t_out, _ = turn_between(d[j - 2:j + 1], tail, radius)":
        "equivalent: turn_between reads the last two points of its first argument only",
    "_bridge | continue": _ORDER,
    "join_bridges | if idx.size == 1:":
        ("not killed (equivalent in use): with one transit vertex _bridge has no exit to try (m = 3), only the "
         "direct turn along the clipped line, through the zone the gap is for; searched 5 offsets x 5 radii x 2 "
         "boxes: none joined, as with the mutant"),
    "join_bridges | before = route[1]":
        "equivalent: before is read only when a - 1 < last, after a bridge was joined, which sets it",
    "join_bridges | seq = np.vstack([route[a - 1] if a - 1 > last else before, route[a:b + 2]])":
        ("not killed: with two line vertices between bridges the mutant turns from the previous turn's last point "
         "instead of the line vertex after it; both lie on the line's approach, and the joined result still fits "
         "and is clear (test_two_bridges_with_two_line_vertices_between_are_both_joined)"),
    "join_bridges | seq = np.vstack([route[a - 1] if a - 2 >= last else before, route[a:b + 2]])":
        ("not killed: with two line vertices between bridges the mutant turns from the previous turn's last point "
         "instead of the line vertex after it; both lie on the line's approach, and the joined result still fits "
         "and is clear (test_two_bridges_with_two_line_vertices_between_are_both_joined)"),
    "join_bridges | before = inner[-1] if inner.shape[1] else route[a]":
        "equivalent in use: inner.shape[1] is 3; an empty inner (a turn without a point) was never produced",
    "join_bridges | before = inner[-2] if inner.shape[0] else route[a]":
        ("not killed: the shared-vertex case turns from the joined turn's last-but-one point, on the same final arc; "
         "the result still fits R as flown (test_two_bridges_sharing_a_vertex_fly_as_turns_of_the_radius)"),
})
# audit 14's neighbouring cells of Terrain.elevation_bounds (merged from main, re-run 21:10 UTC)
_SHARED = ("not killed (the bound's slack): a cell's coefficients come from its four nodes, which it shares with the "
           "cells on either side, so the cell itself or the one two over sees the same cliff within a small factor, "
           "and the bound has ~60x to spare (none of 120 000 points beside cliffs on grid lines outside it)")
_SYM = "equivalent: the offsets (-1, 0, 1) are symmetric, so subtracting them runs over the same cells"
REASONS.update({
    "Terrain.elevation_bounds | for dj in (-2, 0, 1):": _SHARED,
    "Terrain.elevation_bounds | for dj in (-1, 1, 1):": _SHARED,
    "Terrain.elevation_bounds | for dj in (-1, 0, 2):": _SHARED,
    "Terrain.elevation_bounds | for di in (-2, 0, 1):": _SHARED,
    "Terrain.elevation_bounds | for di in (-1, 1, 1):": _SHARED,
    "Terrain.elevation_bounds | for di in (-1, 0, 2):": _SHARED,
    "Terrain.elevation_bounds | near = self._coef[np.clip(j - dj, 0, ny - 1), np.clip(i + di, 0, nx - 1)]": _SYM,
    "Terrain.elevation_bounds | near = self._coef[np.clip(j + dj, 0, ny - 1), np.clip(i - di, 0, nx - 1)]": _SYM,
})
# main's split of terrain_track (_following_leg, _flags): the same survivors under the new names
REASONS.update({
    "_flags | w = as_points(waypoints).reshape(-2, 3)": _NEG,
    "_flags | f = np.asarray(follow, dtype=bool).reshape(-2)": _NEG,
    **{k.replace("terrain_track |", "_following_leg |"): v for k, v in REASONS.items()
       if k.startswith("terrain_track | t = np.where") or k.startswith("terrain_track | inner =")},
})
# main since 27efd1d: a terrain-frame leg's straight line is not flown (its track alone enters)
REASONS.update({
    "_zone_approach | seg, si = exact.entries(np.stack([points[:-1], points[1:]], axis=2))":
        ("equivalent since the straight line of a terrain-frame leg is dropped: the straight legs kept (not "
         "terrain-frame) are flown as themselves in terrain_track's track, whose entries (more) already hold "
         "theirs; the garbage segments' entries are filtered or repeat them"),
})

# wave 13's new and changed code (the session of 6 Dec 2026 from 20:00, d226df0..00dc173): the .plan's item walk
# and what reads it (waypoints, terrain-frame legs, deploy record), mission check as flown, the export's
# terrain-frame items and MOOS floor, the CLI's durations, numba's BLAS probe, validate's numpy survey bounds
QGC_ITEMS, TERRAIN_FRAME = "auvplan.io.missions.readback.qgc_items", "auvplan.io.missions.readback.terrain_frame"
DEPLOY, DEPLOY_READ = "auvplan.io.missions.deploy", "auvplan.io.missions.readback.deploy_files"
DURATIONS, JIT = "auvplan.app.durations", "auvplan.runtime.jit"
SURVEY_RESULTS = "auvplan.io.results.survey"
MODULES.update({
    # the seabed-following track once per leg: its pitch, its deepest vertex, the check measured on it
    "flown-track": Target(_fns(TERRAIN_LEGS, "_following_leg", "flown_track", "check_as_flown")),
    # a .plan's items in the vehicle's order, and the readers that share the walk
    "qgc-walk": Target(
        _fns(QGC_ITEMS, "_simple", "_pattern", "plan_items") + _fns(TERRAIN_FRAME, "terrain_legs")
        + _fns(DEPLOY_READ, "_qgc") + _fns(PARSERS, "parse_qgc_plan")
        + _fns(FORMATS, "read_mission", "_parse", "check_mission_file"),
    ),
    # the export's terrain-frame items and the MOOS altitude floor (DeployInfo.leg_floor)
    "deploy-terrain": Target(
        ((DEPLOY, "deploy_info", "altitude = items = floor = None", "pay = None"),)
        + _fns(DEPLOY, "_followed_free", "_terrain_items"),
    ),
    # the command line's durations and departure offsets
    "durations": Target(_fns(DURATIONS, "parse_duration", "is_offset")),
    # numba's registries loaded without scipy.linalg, and each kernel's cache made at its first compile
    "blas-probe": Target(
        _fns(JIT, "_BlasProbe.find_spec", "_blas_installed", "_CacheOnUse.__getattr__", "_probe_blas"),
    ),
    # validate's survey checks decided by the numpy seabed's bound (the compiled seabed when not conclusive)
    "survey-bounds": Target(
        _fns(SURVEY_RESULTS, "_check_seabed", "check_survey_size", "_swath", "_swath_bounds", "_seabed_bounds"),
    ),
})

# wave 13's targets (run 6 Dec 2026, 22:55-23:25 UTC): the survivors argued (docs/mutants.md section 5)
_ONE_WP = ("equivalent: with one waypoint leg_pitch_deg gives no leg either (np.diff of one row), and with none "
           "the same empty array")
_BELOW_LIMIT = "boundary: a leg's pitch within 1e-9 deg of the limit (or of its straight pitch), the tolerance itself"
_ALWAYS_TWO = ("equivalent in use: deploy_info's only caller (export.deploy_for) passes a mission's waypoints, a start "
               "and a goal at least; with one waypoint leg_figures of no leg gives the same empty array")
_FALLBACK = ("equivalent: it only makes the numpy bound inconclusive (or stricter) more often, and the compiled seabed "
             "then decides the same verdict (the bound path never passes what the compiled one refuses)")
REASONS.update({
    "_following_leg | n = np.clip(np.ceil(np.sqrt(np.abs(q2) / (4.0 * SAG_M))), 1, 100001).astype(np.intp)":
        ("equivalent in use: the cap binds only for a piece whose curvature term |q2| exceeds 4e8 m (1e5 chords of "
         "a 1 cm sag), 20 000 times the Earth's relief in one grid cell"),
    "flown_track | pitch = np.abs(leg_pitch_deg(w)) if w.shape[0] >= 1 else np.zeros(0)": _ONE_WP,
    "flown_track | pitch = np.abs(leg_pitch_deg(w)) if w.shape[1] > 1 else np.zeros(0)": _ONE_WP,
    "check_as_flown | n = max(w.shape[0] - 1, 1)":
        ("equivalent: with one waypoint the original fails too (alt.min() of no leg: ValueError), and its callers "
         "refuse a mission of fewer than 2 waypoints first (check_mission_file)"),
    "check_as_flown | k = int(np.argmin(alt)) if np.isfinite(alt).all() else -1":
        ("equivalent: the legs' altitudes are all finite (a seabed, clamped to its edge beyond its data) or all "
         "infinite (none), so any = all"),
    ("_qgc | exc = [np.asarray(p['polygon'], dtype=float) for p in fence.get('polygons', []) if not "
     "p.get('inclusion', False)]"):
        ("not killed (not this wave's line): a fence polygon without an 'inclusion' key, which QGC's plan format "
         "requires, is read as neither an inclusion nor an exclusion; the mutant reads it as an exclusion"),
    ("parse_qgc_plan | kept = next((it for it, r in zip(items, rows[1:], strict=False) if abs(r[2]) < ZERO_ALT_M), "
     "None)"): "equivalent: rows holds the home and one row per item, so the two sequences are always as long",
    "parse_qgc_plan | if t.any() or seabed is not None:":
        ("equivalent: without a terrain-frame item z[t] += ... adds to no element; a terrain-frame item without a "
         "seabed was refused above"),
    ("read_mission | size = np.nan_to_num(np.abs(np.atleast_2d(waypoints)), nan=1.0).max(axis=-1, "
     "initial=0.0)"): "equivalent: a NaN counted as 0 m or 1 m is under the 4e7 m bound either way",
    ("read_mission | size = np.nan_to_num(np.abs(np.atleast_2d(waypoints)), nan=0.0).max(axis=1, "
     "initial=0.0)"): "equivalent: the array is 2-D (np.atleast_2d), where axis 1 is axis -1",
    ("read_mission | size = np.nan_to_num(np.abs(np.atleast_2d(waypoints)), nan=0.0).max(axis=-1, "
     "initial=1.0)"): "equivalent: a floor of 1 m instead of 0 m is under the 4e7 m bound either way",
    "deploy_info | floor = leg_figures(world, w[:-1], w[1:], 'held')[0] if len(w) >= 1 else np.zeros(0)": _ALWAYS_TWO,
    "deploy_info | floor = leg_figures(world, w[:-1], w[1:], 'held')[0] if len(w) > 1 else np.zeros(1)": _ALWAYS_TWO,
    "_terrain_items | if len(w) >= 1:":
        "equivalent: with one waypoint items[1:] is empty whatever the flight of no leg gives",
    ("_terrain_items | rounded = np.degrees(np.arctan(np.tan(np.radians(pitch)) + ROUNDED_RISE_M / np.hypot(*np.diff("
     "w[:, :3], axis=0).T)))"):
        ("equivalent: np.hypot's third positional argument is its output array, so hypot(dx, dy, dz) still returns "
         "the horizontal length (written over dz's temporary)"),
    ("_terrain_items | items[1:] = ((rounded < max_pitch_deg + 1e-09) | (pitch <= np.abs(leg_pitch_deg(w)) + 1e-09)) "
     "& _followed_free(world, w, flown.track, flown.leg)"): _BELOW_LIMIT,
    ("_terrain_items | items[1:] = ((rounded <= max_pitch_deg - 1e-09) | (pitch <= np.abs(leg_pitch_deg(w)) + "
     "1e-09)) & _followed_free(world, w, flown.track, flown.leg)"): _BELOW_LIMIT,
    ("_terrain_items | items[1:] = ((rounded <= max_pitch_deg + 1e-09) | (pitch < np.abs(leg_pitch_deg(w)) + 1e-09)) "
     "& _followed_free(world, w, flown.track, flown.leg)"): _BELOW_LIMIT,
    "parse_duration | for unit in sorted(units, key=len, reverse=False):":
        ("equivalent: no unit (s, sec, min, m, h, d) ends another, so at most one matches a text's end and the "
         "order of the tries does not matter"),
    "_check_seabed | if bool(np.all(_seabed_bounds(world, px, py)[1] <= below)):":
        ("equivalent: the upper bound is a rounding above the numpy seabed plus its error, so the compiled seabed "
         "lies strictly under it; at hi == below the compiled check passes the area as the mutant does"),
    "check_survey_size | gx, gy = np.meshgrid(np.linspace(x0, x1, 49), np.linspace(y0, y1, 48))":
        ("not killed (the estimate's sampling): 48 or 49 samples a side change the harmonic mean of the spacing "
         "by the seabed's variation between samples; the estimate is pinned nowhere (flat seabeds cannot tell)"),
    "check_survey_size | gx, gy = np.meshgrid(np.linspace(x0, x1, 48), np.linspace(y0, y1, 49))":
        ("not killed (the estimate's sampling): 48 or 49 samples a side change the harmonic mean of the spacing "
         "by the seabed's variation between samples; the estimate is pinned nowhere (flat seabeds cannot tell)"),
    "check_survey_size | if depth.size == 1:":
        ("equivalent in use: it needs exactly one of the 48 x 48 samples under water, in an area _check_seabed "
         "found under water at every one of its denser samples just before"),
    "_swath_bounds | if x.size == 1:": _FALLBACK,
    "_swath_bounds | wet, dry = (hi <= 0.0, lo >= 0.0)":
        ("equivalent: a sample whose bound reaches exactly 0 counted as water gives a zero reach, hence a smaller "
         "least spacing: the bound's check can only fail, and the compiled seabed decides"),
    "_swath_bounds | wet, dry = (hi < 0.0, lo > 0.0)": _FALLBACK,
    "_seabed_bounds | inf = np.full(np.shape(x), np.inf)":
        ("equivalent in use: reached only without a seabed, which a survey refuses first ('a survey needs a seabed "
         "([terrain])'); _check_seabed asserts one"),
    "_seabed_bounds | return (np.nextafter(zb - err, np.inf), np.nextafter(zb + err, np.inf))":
        ("not killed (the bound's slack): the lower end moves two roundings inward, within the ~60x slack of "
         "Terrain.elevation_bounds' error (clearly-free's survivors)"),
})

# mutants17's second round: mission check of a .plan as flown beyond the seabed check (its helm report numbered from
# the home, its legs' pitch and depth, its navigation on the seabed-following track) and its leg speeds (the walk)
APP_SPEEDS = "auvplan.io.missions.readback.speeds"
MODULES.update({
    "check-as-flown": Target(
        _fns(APP_CHECK, "_from_home", "_flown_pitch_depth", "_navigation_as_flown")
        + _fns(APP_SPEEDS, "_qgc", "_speed", "read_leg_speeds"),
    ),
})
_NAV_EDGE = ("boundary: a leg's predicted error within 1e-9 of max_error_m times itself, the tolerance "
             "check_navigation uses too")
REASONS.update({
    "_navigation_as_flown | for j, kind in zip(ends, kinds, strict=False):":
        "equivalent: ends holds one track vertex per waypoint (the first, then each leg's last), as kinds one kind",
    ("_navigation_as_flown | length = np.hypot(*np.diff(track[:, :2], axis=0).T) - 1e-300"):
        ("equivalent: +-1e-300 vanishes beside any positive length, and a vertical leg's one segment of length 0 "
         "gives lock x (-1e-300) / (-1e-300), its own lock, as with +1e-300"),
    ("_navigation_as_flown | length = np.hypot(*np.diff(track[:, :3], axis=0).T) + 1e-300"):
        "equivalent: np.hypot's third positional argument is its output array (the horizontal length still)",
    "_navigation_as_flown | if (over := np.flatnonzero(err >= nav.max_error_m * (1.0 + 1e-09))).size:": _NAV_EDGE,
    "_navigation_as_flown | if (over := np.flatnonzero(err > nav.max_error_m / (1.0 + 1e-09))).size:": _NAV_EDGE,
    "_navigation_as_flown | if (over := np.flatnonzero(err > nav.max_error_m * (1.0 - 1e-09))).size:": _NAV_EDGE,
    "_speed | value = it.params[1] if len(it.params) >= 1 else None":
        "equivalent: plan_items refuses an item without exactly 7 parameters, so params[1] is always there",
    "_speed | value = it.params[1] if len(it.params) > 2 else None":
        "equivalent: plan_items refuses an item without exactly 7 parameters, so params[1] is always there",
})
# main since audit 17 (f821d60): +inf is refused with the speeds over 100 m/s before this line
REASONS.update({
    "read_leg_speeds | return a if bool(np.any(np.isfinite(a))) and bool(np.all(a > 0)) else None":
        ("equivalent since audit 17: +inf is refused above (a > MAX_SPEED_MPS), and NaN and -inf fail a > 0, so "
         "all(a > 0) alone keeps only finite speeds"),
})
# main since audit 17 (11e2491): the null-island refusal walks the same two sequences
REASONS.update({
    ("parse_qgc_plan | null = next((it for it, r in zip(items, rows[1:], strict=False) if max(abs(r[0]), abs(r[1])) "
     "< ZERO_LATLON_DEG), None)"):
        "equivalent: rows holds the home and one row per item, so the two sequences are always as long",
})

# ---- round 6 (7 Dec 2026, after midnight; docs/mutants.md section 6): this session's new code
# the speeds' rewrite (a .plan's legs before its first speed command carry none; the holds and their 16-bit limit)
# and the QGC writer's leading MAV_CMD_DO_CHANGE_SPEED
QGC_WRITER = "auvplan.io.missions.formats"
MODULES.update({
    "speeds-rewrite": Target(
        _fns(APP_SPEEDS, "_qgc", "_read", "judged_leg_speeds", "_ranges", "_refuse_holds", "read_holds")
        + _fns(QGC_WRITER, "_change_speed")
        + ((QGC_WRITER, "to_qgc_plan", "v = leg_speeds(speed", "alt = deploy.altitude"),),
    ),
})
REASONS.update({
    "_refuse_holds | p1 = it.params[0] if it.command in (16, 19) else 1":
        ("equivalent: a position that is not a waypoint or a timed loiter holds no stored time; 0 and 1 both lie "
         "within the 16-bit range 0-65535, so neither is refused"),
    "read_holds | if isinstance(p1, bool) or not isinstance(p1, (int, float)) or (not p1 >= 0):":
        ("equivalent: it differs only at p1 = 0 (and -0.0), read as 0 s either way; NaN fails both comparisons, a "
         "negative hold is 0 here under both and refused just after (_refuse_holds)"),
})

# the vector files' guard (a FIFO, a device, an OGR VRT / WFS / pipeline refused by its first bytes; GDAL offline)
# and the dense zone files' bounds (a footprint of >10 000 vertices simplified and grown; the zone and vertex caps)
GUARD, DENSE = "auvplan.io.data.vector.guard", "auvplan.io.data.vector.dense"
MODULES.update({
    "vector-guard": Target(
        _fns(GUARD, "check_source", "offline") + _fns(DENSE, "lean", "check_zone_count", "check_zone_vertices"),
    ),
})
REASONS.update({
    "check_zone_vertices | total = int(shapely.get_num_coordinates(footprints).sum()) if footprints else 1":
        "equivalent: no footprint counts 0 or 1 vertex, both far under the 2,000,000 allowed",
})

# merge_short_legs' exact test of the straight leg (2c32d2a) and the zone reader's repair and names (audit 18)
MISSION_LEGS, VZONES = "auvplan.guidance.mission.legs", "auvplan.io.data.vector.zones"
VFOOTPRINTS = "auvplan.io.data.vector.footprints"
MODULES.update({
    "merge-exact": Target(_fns(MISSION_LEGS, "_droppable", "merge_short_legs")),
    "zone-names": Target(_fns(VFOOTPRINTS, "_repaired") + _fns(VZONES, "_feature_names")),
})
_MERGE_TOL = ("boundary: a merged leg's pitch within 1e-9 deg of the limit or of the steeper old leg, the tolerance "
              "itself")
_MERGE_ENDS = ("equivalent: the mission's ends are kept by both guards (pinned and 0 < j < len(q) - 1); the mutant "
               "drops one of the two, the other still keeps them")
REASONS.update({
    "_droppable | if float(np.linalg.norm(b - a)) < 0.0:":
        ("not killed (conservative): a new leg of no length (A, V, A) then goes through the general tests (pitch 0, "
         "the exact test of the point A, its envelope), which can only keep V more often, never merge unsafely"),
    "_droppable | if float(np.linalg.norm(b + a)) <= 0.0:":
        ("not killed (conservative): a new leg of no length (A, V, A) then goes through the general tests (pitch 0, "
         "the exact test of the point A, its envelope), which can only keep V more often, never merge unsafely"),
    "_droppable | if new_pitch >= max(max_pitch_deg, float(np.abs(leg_pitch_deg(old)).max())) + 1e-09:": _MERGE_TOL,
    "_droppable | if new_pitch > max(max_pitch_deg, float(np.abs(leg_pitch_deg(old)).max())) - 1e-09:": _MERGE_TOL,
    "_droppable | free = world.segments_free(segs, moving=False, ends_free=False)":
        ("equivalent in safety: the convex tests then decided by the ends differ only where an end of the new leg, "
         "a waypoint of the mission, breaks a depth limit or the bounds: that end's old leg fails too, and the "
         "mission fails its check at that waypoint whatever is merged"),
    "merge_short_legs | w = np.asarray(waypoints, dtype=float).reshape(-2, 3)":
        "equivalent: numpy infers the length of any negative dimension, -2 as -1",
    "merge_short_legs | if n < 3 and min_leg <= 0.0:":
        ("equivalent: with fewer than 3 waypoints no vertex is interior (every short leg stuck), with min_leg <= 0 "
         "no leg is shorter: the loop keeps every waypoint, as the early return"),
    "merge_short_legs | if n < 3 or min_leg < 0.0:":
        "equivalent: with min_leg = 0 no leg is shorter than 0, so the loop keeps every waypoint",
    "merge_short_legs | pinned[[0, -1]] = False": _MERGE_ENDS,
    "merge_short_legs | continue":
        "equivalent: with no short leg left every later pass finds none either (only time: at most n passes)",
    "merge_short_legs | if 0 <= j < len(q) - 1 and (not pinned[idx[j]]) and _droppable(world, q, j, max_pitch_deg):":
        _MERGE_ENDS,
    "merge_short_legs | if 0 < j <= len(q) - 1 and (not pinned[idx[j]]) and _droppable(world, q, j, max_pitch_deg):":
        _MERGE_ENDS,
    "merge_short_legs | if 0 < j < len(q) + 1 and (not pinned[idx[j]]) and _droppable(world, q, j, max_pitch_deg):":
        _MERGE_ENDS,
})

# ---- round 7 (7 Dec 2026, ~02:30; docs/mutants.md section 7, mutants20): this session's hostile20/fix20 code
# holds on station (the last item's hold, Traverse.end_hold) and their drift without bottom lock, the launch band,
# the readers' new guards (a GeoJSON's CRS, a tide file, the 50 m/s current cap, run.npz's arrays, bench rows),
# the simulation's step cap and the zones' nearest-distance kernel
END_BUDGET, NAV_BUDGET, NAV_MISSION = "auvplan.endurance.budget", "auvplan.nav.budget", "auvplan.nav.mission"
PARSED, MEN = "auvplan.io.missions.parsed", "auvplan.io.missions.energy"
JSONCRS, TIDECHECK = "auvplan.io.data.vector.jsoncrs", "auvplan.io.data.ocean.tidecheck"
OCURRENTS, READBACK, ROWS = "auvplan.io.data.ocean.currents", "auvplan.io.results.readback", "auvplan.app.bench.rows"
ZEXACT = "auvplan.world.zones.exact"
MODULES.update({
    "hold-station": Target(
        _fns(END_BUDGET, "Traverse.duration", "_held_water", "budget_of", "_blocked_hold", "_verdict")
        + ((END_BUDGET, "traverse", "end = float(hold[-1])", "return Traverse("),),
    ),
    "hold-drift": Target(
        _fns(NAV_BUDGET, "hold_drift", "mission_budget")
        + ((NAV_MISSION, "check_navigation", "budget = mission_budget(", "grown in the last waypoint's hold"),),
    ),
    "launch-band": Target(
        ((LIMITS, "waypoint_limits"), (LIMITS, "WaypointLimits.reasons", "if self.outside_depth_band:",
                                       "outside the depth band (waypoint")),
    ),
    "parse-once": Target(_fns(PARSED, "parse_once", "loads", "remembered") + _fns(MEN, "file_energy_flight")),
    "readers20": Target(
        _fns(JSONCRS, "_stated", "check_geojson_crs")
        + _fns(TIDECHECK, "_number", "_list", "_tables", "_station", "check_tide_doc")
        + ((OCURRENTS, "_component", "if np.isinf(arr).any():", "declare a fill value as _FillValue"),
           (OCURRENTS, "_finish", "for c, arr in comps.items():", "raise DataError(")),
    ),
    "readback-rows": Target(_fns(READBACK, "_points", "_check_arrays") + _fns(ROWS, "read_rows")),
    "step-cap": Target(_fns(SIM_LOOP, "_check_steps")),
    "zones-near": Target(_fns(ZEXACT, "near_distance_kernel", "_near_zones"), jit=False),
})
_SHAPE_ONLY = "equivalent: dur only gives the shape of held and rest (every figure uses t_end, t_start and moving)"
_RESERVE_TOL = ("boundary: the verdict's 1e-9 x battery_wh tolerance itself (a margin or a remaining energy exactly at "
                "the reserve's floor)")
REASONS.update({
    "budget_of | dur = t_end + t_start": _SHAPE_ONLY,
    "budget_of | rest = model.power(0.0) / np.ones(dur.shape)": "equivalent: a division by ones",
    "_verdict | if margin <= -1e-09 * model.battery_wh:": _RESERVE_TOL,
    "_verdict | over = int(np.argmax(remaining <= floor))": _RESERVE_TOL,
    "_verdict | if over == cum.size - 1 and end_wh > 0 and (remaining[-1] + end_wh > floor):": _RESERVE_TOL,
    "_verdict | if over == cum.size - 1 and end_wh >= 0 and (remaining[-1] + end_wh >= floor):":
        ("equivalent: with end_wh = 0 the test is remaining[-1] >= floor, false whenever the reserve is entered on "
         "the last leg (remaining[over] < floor)"),
    "traverse | end = float(hold[-1]) if ok and held_on[-1] and (hold[-1] >= 0.0) else 0.0":
        "equivalent: a hold of 0 s gives end = 0.0 either way, and no node is added (if end > 0.0)",
    "waypoint_limits | w = as_points(waypoints).reshape(-2, 3)":
        "equivalent: numpy infers the length of any negative dimension, -2 as -1",
    ("WaypointLimits.reasons | side = f'deeper than max_depth_m = {self.max_depth_m:g}' if depth >= self.max_depth_m "
     "else f'shallower than min_depth_m = {self.min_depth_m:g}'"):
        "equivalent: a waypoint at exactly max_depth_m is in the band, never listed outside it",
    "check_geojson_crs | if data.find(b'\"crs\"') <= 0:":
        ("equivalent: a file whose first bytes are \"crs\" is a JSON string, not an object: it is left alone a few "
         "lines below (not a dict) either way"),
    "check_geojson_crs | if data.find(b'\"crs\"') < 1:":
        ("equivalent: a file whose first bytes are \"crs\" is a JSON string, not an object: it is left alone a few "
         "lines below (not a dict) either way"),
    "_number | span = '' if (lo, hi) == (math.inf, math.inf) else f' in [{lo:g}, {hi:g}]'":
        "equivalent: every caller passes both ends, so (lo, hi) is never (-inf, inf) and the range is always named",
    ("_finish | big = np.abs(np.where(np.isfinite(arr), arr, 1.0)) > MAX_CURRENT_MPS"):
        "equivalent: the placeholder of a NaN (a land cell) is 0 or 1 m/s, both far under the 50 m/s cap",
})
_MINLENGTH = ("equivalent: every leg holds at least one sample, so np.bincount's own length is already N - 1; a "
              "smaller minlength changes nothing")
_LEG_EDGE = "boundary: a leg's predicted error within 1e-9 of max_error_m times itself, the tolerance itself"
REASONS.update({
    "mission_budget | p = np.asarray(points, dtype=float).reshape(-2, 3)":
        "equivalent: numpy infers the length of any negative dimension, -2 as -1",
    "mission_budget | fixes = [i for i, k in enumerate(kinds) if k and i >= 0]":
        ("equivalent: a fix at waypoint 0 resets sigma_profile at sample 0 to the start's own sigma (fix_sigma of "
         "kinds[0]), with D = 0 there: the same profile"),
    ("mission_budget | share = np.bincount(leg, weights=lock * ds, minlength=p.shape[0] - 2) / np.maximum(np.bincount("
     "leg, weights=ds, minlength=p.shape[0] - 1), 1e-12)"): _MINLENGTH,
    ("mission_budget | share = np.bincount(leg, weights=lock * ds, minlength=p.shape[0] - 1) / np.maximum(np.bincount("
     "leg, weights=ds, minlength=p.shape[0] - 2), 1e-12)"): _MINLENGTH,
    ("mission_budget | share = np.bincount(leg, weights=lock * ds, minlength=p.shape[0] - 1) / np.maximum(np.bincount("
     "leg, weights=ds, minlength=p.shape[0] - 1), 1.000000000001)"):
        "equivalent: the floor only divides a leg of no length, whose locked length is 0 too: 0 either way",
    "check_navigation | over = np.flatnonzero(budget.leg_error_m >= nav.max_error_m * (1.0 + 1e-09))": _LEG_EDGE,
    "check_navigation | over = np.flatnonzero(budget.leg_error_m > nav.max_error_m / (1.0 + 1e-09))": _LEG_EDGE,
    "check_navigation | over = np.flatnonzero(budget.leg_error_m > nav.max_error_m * (1.0 - 1e-09))": _LEG_EDGE,
})
# mutants20's survivors of parse-once (file_energy_holds then, its body now file_energy_flight's) and zones-near,
# argued or left open
REASONS.update({
    'loads | if hit is not None and (hit[1] is text or hit[0] == text):':
        'equivalent: hit[0] is text implies hit[0] == text; the equality decides alone (the identity is a shortcut)',
    ('file_energy_flight | waypoints = read_mission(path, world.origin, world.seabed if world.terrain is None els'
     'e None)[0]'):
        ('not killed (a line moved unchanged from mission_file_energy): the seabed handed to the reader only mat'
         'ters for a terrain-frame .plan on a world with a seabed, which no energy test reads'),
    'file_energy_flight | if waypoints.shape[1] < 2:':
        ('not killed (moved unchanged): a one-point file; the readers refuse a .plan or CSV of fewer than two po'
         'ints first'),
    ("file_energy_flight | return ({'energy_status': 'EXACT', 'energy_wh': 1.0}, True, 'energy: a single point, n"
     "othing to fly', None)"):
        ('not killed (moved unchanged): a one-point file; the readers refuse a .plan or CSV of fewer than two po'
         'ints first'),
    ("file_energy_flight | return ({'energy_status': 'EXACT', 'energy_wh': 0.0}, False, 'energy: a single point, "
     "nothing to fly', None)"):
        ('not killed (moved unchanged): a one-point file; the readers refuse a .plan or CSV of fewer than two po'
         'ints first'),
    'file_energy_flight | if not np.isfinite(waypoints).any():':
        'equivalent: read_mission refuses a waypoint that is not finite before this line (the guard is a second one)',
    ('file_energy_flight | dwell: NDArray[np.float64] | None = None if nav is not None else np.array([nav.surface'
     "_s if k == 'gps' else 0.0 for k in surface_kinds(waypoints)])"):
        ("not killed (moved unchanged, issue 52): the surface fixes' dwell in a file's energy; test_nav and test"
         "_endurance pin it through the planner's path, not through a file"),
    ('file_energy_flight | dwell: NDArray[np.float64] | None = None if nav is None else np.array([nav.surface_s i'
     "f k != 'gps' else 0.0 for k in surface_kinds(waypoints)])"):
        ("not killed (moved unchanged, issue 52): the surface fixes' dwell in a file's energy; test_nav and test"
         "_endurance pin it through the planner's path, not through a file"),
    ('file_energy_flight | dwell: NDArray[np.float64] | None = None if nav is None else np.array([nav.surface_s i'
     "f k == 'gps' else 1.0 for k in surface_kinds(waypoints)])"):
        ("not killed (moved unchanged, issue 52): the surface fixes' dwell in a file's energy; test_nav and test"
         "_endurance pin it through the planner's path, not through a file"),
    'file_energy_flight | station = None if held is None else held >= 0':
        'equivalent: a vertex of no hold marked on station holds for 0 s: traverse acts only where the hold is > 0',
    'near_distance_kernel | count = 1':
        'equivalent: count is always set at the first point (n == 0) before it is read',
    'near_distance_kernel | if n != 0 or px != p[n - 1, 0] or py != p[n - 1, 1]:':
        ('not killed (only time): n != 0 recomputes the zones at each point, the same answers; the first point t'
         'hen reads count 0 and finds no zone: NOT equivalent at n = 0, open'),
    'near_distance_kernel | if n == 1 or px != p[n - 1, 0] or py != p[n - 1, 1]:':
        'not killed: the column test on the first point; open',
    'near_distance_kernel | if n == 0 or px != p[n - 1, 1] or py != p[n - 1, 1]:':
        'not killed: the column test compares x with the point before it; open',
    'near_distance_kernel | if n == 0 or px != p[n - 1, 0] or py != p[n - 1, 2]:':
        'not killed: the column test compares y with the point before it; open',
    'near_distance_kernel | if dh == 0.0 and out_v < 0.0:':
        ("boundary: a point exactly on a zone's floor or ceiling (out_v = 0) inside its footprint: -min(edge, 0)"
         ' = 0 and hypot(0, 0) = 0 either way'),
    'near_distance_kernel | if dh == 0.0 and out_v <= 1.0:':
        'not killed: open (inside the footprint, 0 < out_v <= 1 m then reads as inside)',
    '_near_zones | for jj in range(min(j - reach, 0), min(j + reach, ny - 1) + 1):':
        ("equivalent in value: a negative start row wraps to other cells' lists: more zones measured exactly, th"
         'e minimum unchanged'),
    '_near_zones | for jj in range(max(j - reach, 1), min(j + reach, ny - 1) + 1):':
        "not killed: the scan skips row 0 of the cells; open (no test puts a zone listed only in the grid's first row)",
    '_near_zones | for jj in range(max(j - reach, 0), min(j + reach, ny - 2) + 1):':
        'not killed: the scan skips the last row; open',
    '_near_zones | for ii in range(min(i - reach, 0), min(i + reach, nx - 1) + 1):':
        ("equivalent in value: a negative start column reads other cells' lists: more zones measured, the minimu"
         'm unchanged'),
    '_near_zones | for ii in range(max(i - reach, 1), min(i + reach, nx - 1) + 1):':
        'not killed: the scan skips column 0; open',
    '_near_zones | for ii in range(max(i - reach, 0), max(i + reach, nx - 1) + 1):':
        'equivalent in value: more columns scanned, more zones measured exactly, the minimum unchanged',
    '_near_zones | for ii in range(max(i - reach, 0), min(i + reach, nx + 1) + 1):':
        "equivalent in value: more columns scanned (wrapping to the next row's cells), the minimum unchanged",
    '_near_zones | for ii in range(max(i - reach, 0), min(i + reach, nx - 2) + 1):':
        'not killed: the scan skips the last column; open',
    '_near_zones | for ii in range(max(i - reach, 0), min(i + reach, nx - 1) + 2):':
        'not killed: the scan skips the last column; open',
    '_near_zones | for q in range(start[c], start[c + 2]):':
        "equivalent in value: a cell's list read with the next cell's, more zones measured, the minimum unchanged",
})

# ---- round 8 (7 Dec 2026, ~04:40; docs/mutants.md section 8, mutants21): code no mutation run had seen:
# the deferred load of a cached kernel (issue 56; its hook in jit.KernelCache.load_overload has no mutation
# site under these operators, planted by hand instead), the packages' lazy names, the --out folder's safety
# (prepare_out and its helpers, the atomic write, the clean-up on failure, the lock, the stale temporaries)
CACHELOAD, LAZY = "auvplan.runtime.cacheload", "auvplan.runtime.lazy"
SAFEIO, OUTDIR = "auvplan.io.files.safeio", "auvplan.io.files.outdir"
MODULES.update({
    "cacheload": Target(_fns(CACHELOAD, "enabled", "_registries_loaded", "_declared_symbols", "_elf_undefined",
                             "deferrable", "load_overload", "use_deferred")),
    "lazy": Target(_fns(LAZY, "lazy_attributes")),
    "out-folder": Target(
        _fns(SAFEIO, "prepare_out", "_clean_temporaries", "_one_job", "_check_names", "_discard", "discard_on_failure",
             "atomic_write")
        + _fns(OUTDIR, "acquire", "release", "release_all", "session", "stale_temporaries")),
})
# mutants21: round 8's survivors, and zones-near's (section 7) argued anew
_EDGE_ROW = ("equivalent in value: the grid starts one cell before the lowest footprint and ends at least one past "
             "the highest, so its first and last row and column list only zones their inner neighbour lists too "
             "(test_zones_columns.py pins it); the neighbour is scanned for every point within two cells of a "
             "zone, and a point whose scan held only the edge row or column is over two cells from every zone: "
             "the cap either way")
REASONS.update({
    "prepare_out | if job or written_by(out) != job:":
        "equivalent: with job = '' the added call _record(out, [], '') writes nothing (no new name, no job to set)",
    "_one_job | _replace(out / MANIFEST, (json.dumps({'files': [], 'job': job}, indent=2) + '\\n').encode())":
        "equivalent: the manifest's layout only; every reader parses its JSON",
    "acquire | holder = os.pread(fd, 33, 0).decode('ascii', 'replace').strip() or '?'":
        "equivalent: the holder wrote its pid and a newline, at most 8 bytes (pid_max <= 2^22): 32 or 33 bytes read "
        "the same",
    "acquire | os.ftruncate(fd, 1)":
        "equivalent: the pid written next at offset 0 covers the byte kept (a pid and its newline are >= 2 bytes)",
    "near_distance_kernel | if dh == 0.0 and out_v <= 1.0:":
        ("equivalent: in_v = -out_v for both kinds of band (min(z - lo, hi - z) = -max(lo - z, z - hi)), so with "
         "dh = 0 and out_v > 0 the inside branch gives -min(edge, -out_v) = out_v (edge >= 0), the outside "
         "branch hypot(0, out_v) = out_v; NaN takes the outside branch under both"),
    "_near_zones | for jj in range(max(j - reach, 1), min(j + reach, ny - 1) + 1):": _EDGE_ROW,
    "_near_zones | for jj in range(max(j - reach, 0), min(j + reach, ny - 2) + 1):": _EDGE_ROW,
    "_near_zones | for ii in range(max(i - reach, 1), min(i + reach, nx - 1) + 1):": _EDGE_ROW,
    "_near_zones | for ii in range(max(i - reach, 0), min(i + reach, nx - 2) + 1):": _EDGE_ROW,
})
# ---- round 9 (7 Dec 2026, ~07:00; docs/mutants.md section 9, audit-w17): the last two waves' code no mutation run
# had seen: the exact distance transform and the morphology that stand in for scipy.ndimage (issue 56), the waits a
# mission file carries and their read-back (nav22), a .plan's speeds as WPNav flies them (export22), mission check's
# surface-fix wait
EDT = "auvplan.world.kernels.edt"
DWELL, QGC_SPEEDS = "auvplan.io.missions.readback.dwell", "auvplan.io.missions.readback.speeds"
MFORMATS = "auvplan.io.missions.formats"
MODULES.update({
    "edt": Target(_fns(EDT, "_columns", "_rows_offsets", "_rows_envelope", "distance_transform", "dilate_cross",
                       "window_any"), jit=False),
    "dwell": Target(
        _fns(DWELL, "moos_dwells", "read_dwells") + _fns(MFORMATS, "_dwells", "_varies")
        + ((MFORMATS, "to_moos", "waits = _dwells(", "return \"\\n\".join(lines)"),
           (APP_CHECK, "navigation_check", "short = [] if dwell_s", "legs = [{")),
    ),
    "wpnav-speeds": Target(_fns(QGC_SPEEDS, "along_track_factor", "_vertical_limits", "flown_speeds",
                                "vertical_bound_legs", "_moos")),
})
# audit-w17 (round 9): the survivors argued (docs/mutants.md section 9)
_PATHS = ("equivalent in value: both row passes are exact (the least squared distance, an integer, then one correctly "
          "rounded square root), so which one a mask takes changes only the time (tests/oracles/test_edt.py runs both "
          "on every mask)")
_UNREAD = ("equivalent: breakpoint 0 (zn[0] / zd[0], -infinity) is never read: the pop test reads zn[k] only for "
           "k > 0 and the query zn[j_k + 1] only for j_k < k; a value written at index 1 is overwritten by the next "
           "parabola's push before any read")
_TIE = ("equivalent: at a breakpoint equal to the one compared the two parabolas (or three) give the same value there, "
        "and every value is taken at whole columns")
_NO_LOWER = ("equivalent in value: an offset d with d * d >= max(d2) cannot lower any value (g2 >= 0), so going on "
             "past it changes nothing but the time")
REASONS.update({
    "_rows_offsets | if dd > d2.max():": _NO_LOWER,
    "_rows_offsets | continue": _NO_LOWER,
    "_rows_envelope | zn = np.empty(nx + 2, dtype=np.int64)":
        "equivalent: a longer buffer; at most nx parabolas, so indices up to nx are used either way",
    "_rows_envelope | zd = np.empty(nx + 2, dtype=np.int64)":
        "equivalent: a longer buffer; at most nx parabolas, so indices up to nx are used either way",
    "_rows_envelope | k = -2":
        "equivalent: any negative k skips the pop loop (while k >= 0) and takes the first-parabola branch (k < 0)",
    "_rows_envelope | if k >= 0 and num * zd[k] <= zn[k] * den:":
        "equivalent: at k = 0 zd[0] = 0 and zn[0] = -1, so num * 0 <= -den is false (den > 0): never popped",
    "_rows_envelope | if k > 0 and num * zd[k] < zn[k] * den:": _TIE,
    "_rows_envelope | if k <= 0:":
        "equivalent: after the pop loop k is -1 (no parabola yet) or >= 1 (the loop ends on a push), never 0",
    "_rows_envelope | if k < 1:":
        "equivalent: after the pop loop k is -1 (no parabola yet) or >= 1 (the loop ends on a push), never 0",
    "_rows_envelope | v[0], zn[1], zd[0] = (q, -1, 0)": _UNREAD,
    "_rows_envelope | v[0], zn[0], zd[1] = (q, -1, 0)": _UNREAD,
    "_rows_envelope | v[0], zn[0], zd[0] = (q, 1, 0)": _UNREAD,
    "_rows_envelope | v[0], zn[0], zd[0] = (q, -2, 0)": _UNREAD,
    "_rows_envelope | v[0], zn[0], zd[0] = (q, -1, 1)": _UNREAD,
    "_rows_envelope | while j_k < k and zn[j_k + 1] <= j * zd[j_k + 1]:": _TIE,
    "distance_transform | if ny * nx * nx < SMALL:": _PATHS,
    "distance_transform | if ny * nx * nx > SMALL:": _PATHS,
    "distance_transform | if ny * nx / nx <= SMALL:": _PATHS,
    "distance_transform | if ny / nx * nx <= SMALL:": _PATHS,
})
_GPS_SURFACE = ("equivalent: a 'gps' fix is only ever a waypoint within 0.5 m of the surface (surface_kinds, and "
                "fix_kinds matches a fixes.csv gps row to surface waypoints only), so the depth test is always true "
                "for it")
REASONS.update({
    "_dwells | d = np.zeros(n) if dwell is None else np.asarray(dwell, dtype=float).reshape(-2)":
        "equivalent: numpy takes any negative size as the one unknown dimension: reshape(-2) flattens as -1 does",
    "_varies | return bool(v.size) and bool(np.ptp(v) >= 1e-09)":
        "boundary: per-leg speeds whose spread is exactly 1e-9 m/s",
    ("navigation_check | short = [] if dwell_s is None else [i for i, k in enumerate(kinds[:-1]) if k == 'gps' "
     "and points[i, 2] <= 0.5 and (dwell_s[i] < nav.surface_s - 0.5)]"): _GPS_SURFACE,
    ("navigation_check | short = [] if dwell_s is None else [i for i, k in enumerate(kinds[:-1]) if k == 'gps' "
     "and -points[i, 2] <= 1.5 and (dwell_s[i] < nav.surface_s - 0.5)]"): _GPS_SURFACE,
    ("navigation_check | short = [] if dwell_s is None else [i for i, k in enumerate(kinds[:-1]) if k == 'gps' "
     "and -points[i, 2] <= 0.5 and (dwell_s[i] <= nav.surface_s - 0.5)]"):
        ("boundary: a wait of exactly surface_s - 0.5 s (a .plan holds whole seconds: never; a MOOS duration "
         "could); 119 s for 120 fails and 120 passes under both (test_audit23_launch_fix.py)"),
    "along_track_factor | return np.where(flat > 0.0, full / np.where(flat >= 0.0, flat, 1.0), 1.0)":
        ("equivalent in value: the inner placeholder divides only where the outer where takes 1.0 (a plumb or empty "
         "leg); the mutant divides by 0 there (a RuntimeWarning), its inf or nan discarded"),
    "along_track_factor | return np.where(flat > 0.0, full / np.where(flat > 0.0, flat, 2.0), 1.0)":
        "equivalent: the placeholder is used only where the outer where takes 1.0 (a plumb or empty leg)",
    "_vertical_limits | vz = np.where(rise >= 0.0, WPNAV_SPEED_UP_MPS, WPNAV_SPEED_DN_MPS)":
        ("equivalent: a level leg's vertical limit never binds (flown_speeds: v_z * full / 0 = inf against the "
         "command's; vertical_bound_legs: it asks 0 m/s vertically)"),
    "vertical_bound_legs | asked = np.where(flat > 0.0, v * np.abs(rise) / flat, 1.0)":
        ("equivalent: a plumb leg then 'asks' 1 m/s, under both defaults plus the slack (1.501, 2.501): never named "
         "either way"),
    ("vertical_bound_legs | return tuple((int(k) for k in np.flatnonzero(np.isfinite(v) & (asked >= vz + "
     "0.001))))"): "boundary: a leg asking exactly the default plus the 1 mm/s slack",
})
# ---- round 10 (7 Dec 2026, ~09:15; docs/mutants.md section 10, mutants-w18): the last wave's new and changed code:
# the antimeridian cut of the GeoJSON/KML exports and its read-back, the ahead-of-time kernels' argument-type keys
# and their binding at a kernel's call, every kernel's own copies of its callees (linking), the .plan's fence
# storage, a glider's yos per surfacing cycle, the launch's dive in the navigation budget, and the clearance under
# the navigation error against static obstacles and charted zones (with the zones' R-tree broad phase)
ANTIMERIDIAN, AOT, LINKING = "auvplan.io.missions.antimeridian", "auvplan.runtime.aot", "auvplan.runtime.linking"
DEPLOY_FORMATS, GLIDER = "auvplan.io.missions.deploy_formats", "auvplan.vehicles.glider"
NAV_BUDGET, NAV_CLEARANCE = "auvplan.nav.budget", "auvplan.nav.clearance"
ZONE_POINTS = "auvplan.world.zones.points"
MODULES.update({
    "antimeridian": Target(_fns(ANTIMERIDIAN, "crosses", "cut_line", "join_line", "_same_cut", "cut_ring",
                                "join_rings")),
    "aot-keys": Target(
        _fns(AOT, "_numpy_scalars", "_key_into", "arg_key", "args_key", "runtime_key")
        + (("auvplan.runtime.jit", "_Deferred.__call__"),)),
    "linking": Target(_fns(LINKING, "bind_locally", "OwnCodeLibrary._optimize_final_module",
                           "OwnCodeCompiler.compile_extra")),
    "fence-storage": Target(_fns(DEPLOY_FORMATS, "fence_bytes", "fence_storage_problem")),
    "glider-yos": Target(_fns(GLIDER, "yos_per_cycle")),
    "launch": Target(_fns(NAV_BUDGET, "launch_point", "_launched", "launch_drift", "mission_budget")),
    "nav-hazards": Target(
        _fns(NAV_CLEARANCE, "_band_trace", "zone_within", "zone_safe_radius", "obstacle_within",
             "obstacle_safe_radius", "hazard_safe_radius")
        + _fns(ZONE_POINTS, "Zones.traces_near")),
})
# mutants-w18 (round 10): the survivors argued (docs/mutants.md section 10)
_NEG = "equivalent: numpy infers the length of any negative dimension, -2 as -1"
_EDGE_TOL = ("boundary: a longitude (latitude, altitude) exactly _ON_EDGE_DEG (z_tol) from the edge (the other point); "
             "the exports write 9 decimals, so 180 - 1e-9 is read 1.00000008e-9 away: never exactly at the tolerance")
_STEP_180 = ("boundary: a step of exactly 180 degrees of longitude, as long either way round; the cut there is valid "
             "too (every piece's steps stay within 180)")
_WRAP = "equivalent: x - 180 and x + 180 are the same modulo 360"
_LAYOUT = ("equivalent: bit 0 of numpy's flags (C-contiguous) is also the layout term's (1 if n & 1), so n & 1025 | "
           "layout = n & 1024 | layout, and n & 3 = n & 2 where n & 1 is 0 (the only case it is read)")
REASONS.update({
    "crosses | return bool(np.any(d >= 180.0))": _STEP_180,
    "cut_line | if abs(step) >= 180.0:": _STEP_180,
    "cut_line | if p.shape[0] < 2 and (not crosses(p[:, 0])):":
        "equivalent: a line of 0 or 1 points never crosses (the loop makes the same one piece), and a line of 2 or "
        "more that does not cross goes through the loop without a cut: one piece, the line's points",
    "cut_line | if p.shape[1] < 2 or not crosses(p[:, 0]):":
        "equivalent: a line has at least 2 columns (lon, lat), and of fewer than 2 points it never crosses",
    "cut_line | for a, b in zip(p[:-1], p[1:], strict=False):": "equivalent: p[:-1] and p[1:] are equally long",
    "cut_line | b_un[0] = b[0] + (360.0 if step <= 0.0 else -360.0)":
        "equivalent: reached only with |step| > 180, never with a step in [0, 1)",
    "cut_line | b_un[0] = b[0] + (360.0 if step < 1.0 else -360.0)":
        "equivalent: reached only with |step| > 180, never with a step in [0, 1)",
    "cut_line | t = (edge - a[0]) / span if span != 0.0 else 1.0":
        ("equivalent in what is read back: span is 0 only from a point on +-180 to one on -+180 (one meridian); the "
         "cut is then at a (t = 0) or at b (t = 1), join_line drops the cut pair either way, and each written piece's "
         "steps stay within 180"),
    "join_line | arrs = [a.reshape(-2, a.shape[-1]) if a.ndim else a.reshape(0, 1) for a in arrs]": _NEG,
    "join_line | arrs = [a.reshape(-1, a.shape[1]) if a.ndim else a.reshape(0, 1) for a in arrs]":
        "equivalent: every piece the readers pass is (k, 3) (readers._lon_lat_alt refuses any other shape)",
    "join_line | arrs = [a.reshape(-1, a.shape[-1]) if a.ndim else a.reshape(1, 1) for a in arrs]":
        "equivalent: a piece is never a 0-d array (readers._lon_lat_alt refuses it before)",
    "join_line | arrs = [a.reshape(-1, a.shape[-1]) if a.ndim else a.reshape(0, 2) for a in arrs]":
        "equivalent: a piece is never a 0-d array (readers._lon_lat_alt refuses it before)",
    "join_line | return np.vstack(out) if out else np.empty((1, 3))":
        "equivalent: out always holds the first piece, so the else is never taken",
    "join_line | return np.vstack(out) if out else np.empty((0, 4))":
        "equivalent: out always holds the first piece, so the else is never taken",
    ("_same_cut | on_edge = abs(abs(a[0]) - 180.0) < _ON_EDGE_DEG and abs(abs(b[0]) - 180.0) <= "
     "_ON_EDGE_DEG"): _EDGE_TOL,
    ("_same_cut | on_edge = abs(abs(a[0]) - 180.0) <= _ON_EDGE_DEG and abs(abs(b[0]) - 180.0) < "
     "_ON_EDGE_DEG"): _EDGE_TOL,
    ("_same_cut | return bool(on_edge and a.size == b.size and (abs(a[1] - b[1]) < _ON_EDGE_DEG) and "
     "np.all(np.abs(a[2:] - b[2:]) <= z_tol))"): _EDGE_TOL,
    ("_same_cut | return bool(on_edge and a.size == b.size and (abs(a[1] - b[1]) <= _ON_EDGE_DEG) and "
     "np.all(np.abs(a[2:] - b[2:]) < z_tol))"): _EDGE_TOL,
    "cut_ring | if not crosses(np.r_[lo, lo[:2]]):":
        "equivalent: the added step lo[0] -> lo[1] is the ring's first edge, already among the steps",
    "cut_ring | un = lo[0] + np.r_[0.0, np.cumsum((np.diff(lo) - 180.0) % 360.0 - 180.0)]": _WRAP,
    "cut_ring | part = shapely.intersection(poly, shapely.box(-180.0 + k, -91.0, 180.0 + k, 90.0))":
        "equivalent: latitudes lie within +-90 (the readers refuse others), so the box's latitude side never cuts",
    "cut_ring | part = shapely.intersection(poly, shapely.box(-180.0 + k, -90.0, 180.0 + k, 91.0))":
        "equivalent: latitudes lie within +-90 (the readers refuse others), so the box's latitude side never cuts",
    "join_rings | arrs = [a[:-1] if a.shape[0] >= 1 and np.array_equal(a[0], a[-1]) else a for a in arrs]":
        "equivalent: differs only for a ring of one point, which is no polygon (shapely refuses it either way)",
    "join_rings | arrs = [a[:-1] if a.shape[1] > 1 and np.array_equal(a[0], a[-1]) else a for a in arrs]":
        "equivalent: the rings are cut to 2 columns just before, so shape[1] is 2 > 1, and a 1-point ring is none",
    "join_rings | arrs = [a[:-1] if a.shape[0] > 2 and np.array_equal(a[0], a[-1]) else a for a in arrs]":
        "equivalent: differs only for a closed ring of 2 points, which is no polygon",
    "join_rings | ref = float(arrs[1][0, 0])":
        ("equivalent: the reference only fixes which whole turn the pieces are moved to: any vertex of a piece of a "
         "ring cut at +-180 lies beside it, and the result is wrapped into [-180, 180) at the end"),
    "join_rings | ref = float(arrs[0][1, 0])":
        ("equivalent: the reference only fixes which whole turn the pieces are moved to: any vertex of a piece of a "
         "ring cut at +-180 lies beside it, and the result is wrapped into [-180, 180) at the end"),
    "join_rings | shift = 360.0 * round((float(np.mean(a[:, 0])) + ref) / 360.0)":
        ("equivalent for pieces of a ring cut at +-180 less than 180 degrees wide: with ref and the means near +-180, "
         "round((m + ref) / 360) - round((m' + ref) / 360) is the same whole turn as with m - ref (test_mutants24_"
         "antimeridian rolls every piece's first vertex, at the equator too)"),
    "join_rings | shift = 360.0 * round((float(np.mean(a[:, 0])) - ref) / 361.0)":
        ("equivalent for pieces less than 180 degrees wide: |mean - ref| then never lies within the 0.5 degree "
         "where dividing by 361 rounds otherwise (about 180)"),
    "join_rings | return np.column_stack([(xy[:, 0] - 180.0) % 360.0 - 180.0, xy[:, 1]])": _WRAP,
    ("OwnCodeCompiler.compile_extra | if self.state.library is None or getattr(codegen, '_library_class', None) is "
     "JITCodeLibrary:"):
        ("equivalent: the pipeline class's compile_extra is reached only from the dispatcher (numba/core/dispatcher.py "
         "_compile_core), which passes no library; the paths that pass one (compile_internal, compile_ir) use "
         "numba's Compiler or call compile_ir, never this method"),
    "_key_into | out.append(value.ndim << 16 | n & 1025 | (1 if n & 1 else n & 2))": _LAYOUT,
    "_key_into | out.append(value.ndim << 16 | n & 1024 | (1 if n & 1 else n & 3))": _LAYOUT,
    "args_key | out.append(v.ndim << 16 | n & 1025 | (1 if n & 1 else n & 2))": _LAYOUT,
    "args_key | out.append(v.ndim << 16 | n & 1024 | (1 if n & 1 else n & 3))": _LAYOUT,
    "args_key | array = _ARRAY[0] if _ARRAY else _numpy_scalars() or _ARRAY[0]":
        ("equivalent in value: on a process's first key only, arrays then go through _key_into, which keys them the "
         "same way (id of the dtype, the same flags and layout)"),
    "launch_point | home: FloatArray = np.asarray(points, dtype=float).reshape(-2, 3)[0].copy()": _NEG,
    "_launched | water = h if water_m is None else np.asarray(water_m, dtype=float).reshape(-2)": _NEG,
    ("_launched | held = np.zeros(p.shape[0]) if held_water_m is None else np.asarray(held_water_m, "
     "dtype=float).reshape(-2)"): _NEG,
    "_launched | h = np.hypot(*np.diff(p[:, :3], axis=0).T)":
        ("equivalent: np.hypot's third positional argument is its out: hypot(dx, dy, out=dz) writes hypot(dx, dy) "
         "into the temporary dz and returns it"),
})
_SCALE = ("equivalent: d (1 +- 1e-12) - 1e-6 stays under d for any distance under 1 000 km (d 1e-12 < 1e-6), and "
          "r_max is the navigation's max_error_m")
_NOT_FIRST = ("equivalent in the verdict: a segment whose pair with zone 0 hit goes on to its other pairs and may "
              "name another zone that is also within (the R-tree's order of pairs is no meaningful order: the "
              "docstring promises a zone within, -1 for none)")
_TWO = "equivalent: the segments are (K, 2, 3): shape[1] is 2, and an empty K gives no pairs either way"
REASONS.update({
    "_band_trace | t0, t1 = (0.0, 1.0) if lo <= a[2] <= hi else (2.0, 0.0)":
        "equivalent: any t0 > t1 = 0 gives None (the level leg outside the band)",
    "_band_trace | return shapely.linestrings([p0, p1]) if t1 >= t0 else shapely.points(p0)":
        "equivalent: a line of two equal points has the point's distance to a polygon (GEOS)",
    "zone_within | seg = np.asarray(segments, dtype=float).reshape(-2, 2, 3)": _NEG,
    "obstacle_within | seg = np.asarray(segments, dtype=float).reshape(-2, 2, 3)": _NEG,
    "Zones.traces_near | s = np.asarray(segments, dtype=float).reshape(-2, 2, 3)": _NEG,
    "zone_within | if not world.zones or seg.shape[1] == 0:": _TWO,
    "zone_safe_radius | if not world.zones or seg.shape[1] == 0:": _TWO,
    "Zones.traces_near | if not self.zones or s.shape[1] == 0:": _TWO,
    "Zones.traces_near | if not self.zones and s.shape[0] == 0:":
        "equivalent: the R-tree of no zones answers no pairs, and a query of no segments none",
    "Zones.traces_near | k, j = self._tree.query(shapely.linestrings(s[:, :, :3]), predicate='dwithin', "
    "distance=reach)": "equivalent: GEOS measures distances in the plane, the z of a 3-D line ignored",
    "zone_within | for k, j in zip(ks.tolist(), js.tolist(), strict=False):":
        "equivalent: the R-tree's pairs come as two arrays of one length",
    "zone_safe_radius | for k, j in zip(ks.tolist(), js.tolist(), strict=False):":
        "equivalent: the R-tree's pairs come as two arrays of one length",
    "zone_within | if out[k] > 0:": _NOT_FIRST,
    "zone_within | if out[k] >= 1:": _NOT_FIRST,
    ("zone_within | hit = world.terrain is not None and float(leg_slack(world.terrain, a, b, r[k])[0]) < "
     "z.above_seabed"): "boundary: a leg's least uncertain altitude exactly the band's height",
    ("zone_safe_radius | r = math.inf if part is None else float(shapely.distance(part, z.footprint)) / (1.0 - "
     "1e-12) - 1e-06"): _SCALE,
    ("zone_safe_radius | r = math.inf if part is None else float(shapely.distance(part, z.footprint)) * (1.0 + "
     "1e-12) - 1e-06"): _SCALE,
    "obstacle_safe_radius | out[near] = np.minimum(out[near], np.maximum(gap / (1.0 - 1e-12) - 1e-06, 0.0))": _SCALE,
    "obstacle_safe_radius | out[near] = np.minimum(out[near], np.maximum(gap * (1.0 + 1e-12) - 1e-06, 0.0))": _SCALE,
    ("zone_safe_radius | return x > reach and world.terrain is not None and (float(leg_slack(world.terrain, p, q, "
     "x)[0]) <= h)"): "boundary: a bisection's radius exactly the trace's distance to the footprint",
    ("zone_safe_radius | return x >= reach and world.terrain is not None and (float(leg_slack(world.terrain, p, q, "
     "x)[0]) < h)"): "boundary: a leg's least uncertain altitude exactly the band's height",
    "zone_safe_radius | while hi - lo >= tol and (not hit(0.0)):":
        "boundary: a bracket exactly tol wide is halved once more (a tighter radius, still on the safe side)",
})
