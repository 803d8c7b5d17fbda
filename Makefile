# Two entry points that work on a fresh machine with only Python 3.11 and make:
#   make demo   set up .venv and run the built-in default scenario end to end
#   make test   set up .venv and run the whole suite (ruff, import layers, pytest)
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-nojit mutants typecheck lint bench clean fuzz kill-points

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[all,test]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/auvplan demo --out results/demo

test: $(STAMP)
	@bash tools/install-chromium.sh
	$(BIN)/python -m pytest
	$(MAKE) --no-print-directory test-nojit

# the scenario property tests at 10x the suite's size (20 000 mutated documents, 600 planned and flown)
fuzz: $(STAMP)
	AUVPLAN_FUZZ_EXAMPLES=20000 AUVPLAN_FUZZ_PLAN_EXAMPLES=600 $(BIN)/python -m pytest -q tests/test_fuzz_scenarios.py

# SIGKILL `run --out` at every atomic replace (before and after), re-run, check the folder is whole
kill-points: $(STAMP)
	$(BIN)/python tools/kill_points.py

# the compiled kernels' modules with numba switched off: the kernels run as plain Python, so
# coverage and tracebacks see their lines (the kernels' own tests and the small ones of the
# lattice, time-optimal and velocity-obstacle kernels; part of `make test`, ~1 min)
test-nojit: $(STAMP)
	NUMBA_DISABLE_JIT=1 $(BIN)/python -m pytest -p no:cacheprovider tests/test_terrain.py tests/test_cost.py \
		tests/test_world.py tests/test_oracles.py tests/test_jit.py tests/test_flow_body.py tests/test_tides.py \
		tests/test_lattice.py::test_compiled_edge_test_agrees_with_the_exact_segment_test_on_every_edge \
		tests/test_avoidance.py::test_vo_choice_clearance_matches_a_fine_simulation_of_its_track \
		tests/test_timeopt.py::test_steady_uniform_current_gives_the_straight_crab_line \
		tests/test_timeopt.py::test_legs_are_fifo \
		tests/test_timeopt.py::test_leg_drifts_back_on_its_line_while_the_current_beats_the_vehicle \
		--deselect tests/test_terrain.py::test_exact_segment_test_agrees_with_dense_sampling

typecheck: $(STAMP)
	$(BIN)/mypy

# the catalogue of hand-planted mutants, then mutation testing of the safety-relevant functions, each mutant
# against every test file importing its module; the summary is written into docs/mutants.md.  Several hours
# on a shared 2-core machine: MODULES="mission formats" runs some modules only
MODULES ?=
mutants: $(STAMP)
	$(BIN)/python tools/oracle_mutants.py
	nice -n 10 $(BIN)/python tools/mutate.py $(MODULES) --jobs 1 --doc docs/mutants.md

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/lint-imports

clean:
	rm -rf $(VENV) results build *.egg-info src/*.egg-info
