# Two entry points that work on a fresh machine with only Python 3.11 and make:
#   make demo   set up .venv and run the built-in default scenario end to end
#   make test   set up .venv and run the whole suite (ruff, import layers, pytest)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-nojit survey-flown mutants typecheck lint bench clean fuzz oracles-full kill-points bench-regress bench-hard docs docs-bench bench-converge \
	bench-flow-flown bench-zones bench-timeopt-front bench-serve-hostile audit-oracles bench-nav bench-front never-silent bench-workers \
	aot-identity nav-plan-run bench-kernel-link

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[all,test]'
	touch $(STAMP)

# then the kernels the demo compiled, compiled ahead of time (auvplan kernels build: a C compiler; ~40 s once, nothing
# when up to date): later commands start without importing numba.  Without a compiler, one line and numba as before
demo: $(STAMP)
	$(BIN)/auvplan demo --out results/demo
	@$(BIN)/auvplan kernels build || true

# pytest over the suite, and beside it the kernels' run with numba off (test-nojit: one process each, so the
# two cores of CI are both used; mypy's run starts beside them too, tests/static/lint_runs.py).  The numba-off
# run and mypy run at nice 10: they fill the second core and never take the suite's (the one process that sets
# make test's time, with its own subprocesses).  The numba-off run's output is kept in a file and shown after
# the suite's; make test fails if either run fails
test: $(STAMP)
	@bash tools/install-chromium.sh
	@log=$$(mktemp); nice -n 10 $(MAKE) --no-print-directory test-nojit > $$log 2>&1 & pid=$$!; \
	trap 'kill $$pid 2>/dev/null' INT TERM; \
	$(BIN)/python -m pytest; main=$$?; wait $$pid; nojit=$$?; \
	echo "== make test-nojit (numba off; run beside the suite above):"; cat $$log; rm -f $$log; \
	test $$main -eq 0 && test $$nojit -eq 0

# the corridor built-in flown: coverage, overlap by an independent ray cast, turns, exports (tests/heavy, minutes)
survey-flown: $(STAMP)
	$(BIN)/python -m pytest -q -s tests/heavy/test_survey_corridor_flown.py

# plan + export and run write the same mission files on the same route (mariana-nav without its fixed route; ~15 s)
nav-plan-run: $(STAMP)
	$(BIN)/python -m pytest -q -s tests/heavy/test_nav24_plan_run.py

# issue 56: the kernels compiled ahead of time give numba's JIT's bits: every built-in's plans and flights dumped with
# the JIT (which fills numba's cache), the kernels built, dumped again with the module; 0 arrays may differ and the
# second run says numba was not imported (docs/performance.md; ~1 min of CPU once the kernels are compiled)
aot-identity: $(STAMP)
	@tmp=$$(mktemp -d); \
	AUVPLAN_AOT=0 nice -n 5 $(BIN)/python tools/identity_dump.py --out $$tmp/jit.npz > $$tmp/jit.log && \
	$(BIN)/auvplan kernels build && \
	AUVPLAN_AOT=1 nice -n 5 $(BIN)/python tools/identity_dump.py --out $$tmp/aot.npz | tail -1 && \
	$(BIN)/python tools/identity_dump.py --compare $$tmp/jit.npz $$tmp/aot.npz; code=$$?; rm -rf $$tmp; exit $$code

# issue 56: a long mission (marcus-wake, a ~31 h flight, then its results, report and exports) in a fresh process,
# every stderr line timed: no silent gap over 2 s (tests/heavy, 12 s CPU, 20-35 s at a load of 5; the suite runs a
# small version)
never-silent: $(STAMP)
	$(BIN)/python -m pytest -q -s tests/heavy/test_never_silent_long.py

# issue 56: the Monte Carlo benchmarks (montecarlo, avoidance, formation, gap) on tiny cases with 1 and with 2 dask
# worker processes: the same rows but for the timing fields (tests/heavy, minutes)
bench-workers: $(STAMP)
	$(BIN)/python -m pytest -q -s tests/heavy/test_benchmarks_workers.py

# the scenario property tests at 10x the suite's size (20 000 mutated documents, 600 planned and flown)
fuzz: $(STAMP)
	AUVPLAN_FUZZ_EXAMPLES=20000 AUVPLAN_FUZZ_PLAN_EXAMPLES=600 $(BIN)/python -m pytest -q tests/property/test_fuzz_scenarios.py

# the oracles' seeded samples at full size: the exit rule of document 000's bodies from 60 starts (the suite: 20)
oracles-full: $(STAMP)
	AUVPLAN_EXIT_STARTS=60 $(BIN)/python -m pytest -q tests/oracles/test_oracles.py -k exit_rule_leaves

# SIGKILL `run --out` at every atomic replace (before and after), re-run, check the folder is whole
kill-points: $(STAMP)
	$(BIN)/python tools/kill_points.py

# the compiled kernels' modules with numba switched off: the kernels run as plain Python, so
# coverage and tracebacks see their lines (the kernels' own tests and the small ones of the
# lattice, time-optimal and velocity-obstacle kernels; part of `make test`, run beside its pytest; ~110 s of CPU).  The exit-rule oracle of
# document 000's bodies is left to the compiled run: its 20 exits (60 in `make oracles-full`) search the field round the body (minutes
# as plain Python)
test-nojit: $(STAMP)
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -p no:cacheprovider tests/oracles/test_terrain.py tests/oracles/test_cost.py tests/oracles/test_cost_kernels.py \
		tests/unit/test_world.py tests/oracles/test_oracles.py tests/integration/test_jit.py tests/oracles/test_flow_body.py tests/oracles/test_tides.py \
		tests/oracles/test_ellipsoid_kernels.py \
		tests/unit/test_lattice.py::test_compiled_edge_test_agrees_with_the_exact_segment_test_on_every_edge \
		tests/unit/test_avoidance.py::test_vo_choice_clearance_matches_a_fine_simulation_of_its_track \
		tests/unit/test_turning.py::test_windowed_velocity_obstacles \
		tests/oracles/test_timeopt.py::test_steady_uniform_current_gives_the_straight_crab_line \
		tests/oracles/test_timeopt.py::test_legs_are_fifo \
		tests/oracles/test_timeopt.py::test_leg_drifts_back_on_its_line_while_the_current_beats_the_vehicle \
		tests/oracles/test_zones.py::test_entries_match_an_independent_shapely_check \
		tests/oracles/test_zones.py::test_signed_distance_is_the_prism_distance_and_never_above_it \
		--deselect tests/oracles/test_terrain.py::test_exact_segment_test_agrees_with_dense_sampling \
		--deselect tests/oracles/test_oracles.py::test_exit_rule_leaves_a_line_distribution_body_just_outside_its_surface

typecheck: $(STAMP)
	$(BIN)/mypy

# the catalogue of hand-planted mutants, then mutation testing of the safety-relevant functions, each mutant
# against every test file importing its module; the summary is written into docs/mutants.md.  Several hours
# on a shared 2-core machine: MODULES="mission formats" runs some modules only
MODULES ?=
mutants: $(STAMP)
	$(BIN)/python tools/oracle_mutants.py
	nice -n 10 $(BIN)/python tools/mutate.py $(MODULES) --jobs 1 --doc docs/mutants.md

# the simulator's and the flow planner's CPU against the previous release, checked out into a temporary
# git worktree and timed in the same run (ratios and bit-identity in results/bench-regress/summary.md)
PREV ?= f5c6a15
bench-regress: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/regress.py --prev $(PREV) --figure-md bench-regress --out results/bench-regress
# THE front-door A/B benchmark (issues 56 and 59): CPU of fresh `python -m auvplan` processes, --version, validate
# and plan --json of every built-in, data inspect of a 1 MB grid, against the previous release's code (a git
# worktree), interleaved rounds, load stated; writes docs/figures/bench-front.md (docs/performance.md)
bench-front: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/front_door.py --prev $(PREV) --rounds 3 --figure-md bench-front --out results/bench-front
# what binding each kernel's calls inside its own code costs (runtime/linking.py): CPU of `plan` compiling its
# kernels into an empty numba cache and loading them, against the commit before it, interleaved (docs/performance.md)
LINK_PREV ?= 45c929ae
bench-kernel-link: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/kernel_link.py --prev $(LINK_PREV) --rounds 3
# the default plan on the six hard problems against the previous release's CODE (f5c6a15, in a git worktree,
# interleaved seed by seed) and its settings on today's code; writes docs/figures/bench-hard-default.md
# (and the `--reference` solver's CPU against REFERENCE_PEER's code, the wave's branch point)
RELEASE ?= f5c6a15
REFERENCE_PEER ?= 07f244c
bench-hard: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/hard.py --seeds 10 --budget 10000 --no-peers --methods iabc iabc/release \
		--release-code $(RELEASE) --reference-peer $(REFERENCE_PEER) --figure-md bench-hard-default \
		--out results/bench-hard
# issue 59: the default plan, IABC alone and ABC alone on the eight hard problems at their own budgets (10 seeds),
# the narrow-channel family before/after (the branch point's code in a worktree) and the plan CPU of every swarm
# built-in against the previous release and the branch point; writes docs/figures/converge-*.md (then `sync`)
BASE ?= 986d447
bench-converge: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/converge.py --seeds 10 --release-code $(RELEASE) --base-code $(BASE) \
		--figures --out results/converge
	$(BIN)/python tools/docs_figures.py sync
# the default flow pipeline flown from 300 near-surface starts per Fig. 7/8 scene (docs/figures/flow-flown.md),
# and mission building (breadth-first Douglas-Peucker) against the recursive one, missions identical
# charted no-go zones (issue 53): 1 000 random missions per planner (~30 min CPU), the CPU with 1 000 zones,
# the default plan's gap to --reference on chagos-reefs (docs/zones.md)
bench-zones: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/zones.py montecarlo --missions 1000 --figure-md zones-montecarlo
	nice -n 5 $(BIN)/python benchmarks/zones.py cpu --zones 1000 --repeats 9 --figure-md zones-cpu
	nice -n 5 $(BIN)/python benchmarks/zones.py gap --figure-md zones-gap

bench-flow-flown: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/flow_flown.py --starts 300 --out results/bench-flow-flown
	nice -n 5 $(BIN)/python benchmarks/mission_build.py --starts 30
# the time-optimal planner's front method (issue 55): exact least times, rotary-tide against Zermelo's bound,
# and CPU against hj_reachability on the same 2-D grid (optional: pip install hj_reachability jax)
bench-timeopt-front: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/timeopt_front.py --out results/bench-timeopt-front
# auvplan serve under hostile requests (issue 48): another request's latency, the server's memory under a
# 300 MB body and 600 concurrent checks; writes docs/figures/serve-hostile.md (quoted in docs/serve.md)
bench-serve-hostile: $(STAMP)
	$(BIN)/python benchmarks/serve_hostile.py --figure
# issue 52: planned fixes flown with a drifting estimate, and the same route with perfect navigation (200 seeds
# each, two processes; docs/navigation.md)
# independent oracles of timeopt (Zermelo in a shear, an independent flight, FIFO) and of the navigation error
# bound (Rice, Monte Carlo): benchmarks/audit_oracles.py, a few minutes of CPU
audit-oracles: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/audit_oracles.py --out results/audit-oracles
bench-nav: $(STAMP)
	nice -n 5 $(BIN)/python benchmarks/nav_drift.py --scenario mariana-nav --seeds 200 --out results/nav --part planned & \
	nice -n 5 $(BIN)/python benchmarks/nav_drift.py --scenario mariana-nav --seeds 200 --out results/nav --part perfect; wait
	$(BIN)/python benchmarks/nav_drift.py --scenario mariana-nav --seeds 200 --out results/nav --part summary --figure nav-drift-w17
# every figure and picture of the docs from its measurement (docs/README.md): the demo, the mission
# table and the quick figures of tools/figures_fast.py (~8 min), the report's screenshots (headless Chromium), the scenario reference, the architecture
# picture, then the figures copied into the docs; tests/golden/test_doc_figures.py keeps them in step
docs: $(STAMP)
	$(BIN)/python tools/docs_figures.py measure
	$(BIN)/python tools/glider_figures.py
	@bash tools/install-chromium.sh
	$(BIN)/python tools/report_screenshots.py --out docs/img
	$(BIN)/python tools/scenario_reference.py
	$(BIN)/python tools/architecture.py
	$(BIN)/python tools/docs_figures.py sync

# the benchmark figures of the docs: avoidance-gauntlet Monte Carlo (500 seeds, predictive; ~15 min on 1 worker),
# the swarm algorithms on marcus-wake (10 seeds, ~5 min), then tools/figures_bench.py's one at a time: document
# 001's laws (10 seeds, ~2 min), chagos-formation (100 seeds, ~15 min idle), the kill points (~5 min), the
# two-model ensemble (100 pairs, ~5 min), endurance predicted against the closed loop (6 runs, ~2 min)
docs-bench: $(STAMP)
	rm -rf results/docs/gauntlet
	$(BIN)/auvplan -q bench --scenarios avoidance-gauntlet --avoidance predictive --seeds 500 --randomise \
		--plan-once --workers 1 --out results/docs/gauntlet
	$(BIN)/python tools/docs_figures.py from-bench results/docs/gauntlet --name gauntlet-predictive
	$(BIN)/python benchmarks/swarm.py --seeds 10 --out results/docs/swarm --figure docs/figures/swarm-marcus.md
	$(BIN)/python tools/docs_figures.py bench doc001-tracking
	$(BIN)/python tools/docs_figures.py bench formation-chagos
	$(BIN)/python tools/docs_figures.py bench kill-points
	$(BIN)/python tools/docs_figures.py bench ensemble-lofoten
	$(BIN)/python tools/docs_figures.py bench endurance-prediction
	$(BIN)/python tools/docs_figures.py sync

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/lint-imports

clean:
	rm -rf $(VENV) results build *.egg-info src/*.egg-info
