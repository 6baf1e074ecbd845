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

.PHONY: setup run launch test test-setup test-fast lint bench render clean help

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

# Five worker processes (pytest-xdist), each on a ROS domain of its own: on two cores the
# extra workers fill the time the ROS tests wait (Nav2's start-up sleeps, DDS discovery,
# browsers). Measured: 3 workers 5 min 56 s, 4 workers 5 min 13 s, 5 workers 4 min 57 s.
# A file's tests stay on one worker, so a module's shared mission runs once; files with slow
# tests go first (tests/conftest.py), in that order.
PYTEST_WORKERS ?= 5
XDIST := -n $(PYTEST_WORKERS) --dist loadfile --no-loadscope-reorder

# The engine tests on py_trees 2.2.3 (13 s of CPU, in one process: two xdist workers cost 3 s
# more for collecting twice, and finished no sooner) run beside the main suite at nice 5: they
# yield to its workers, yet other work on the machine cannot starve them (at nice 19, two
# busy loops held them back five minutes after the main suite had ended). The compatibility
# venv differs from .venv in py_trees only: the property tests that never touch py_trees
# (schema agreement, script and YAML-position fuzzing) run once, in .venv.
NO_PY_TREES := $(addprefix --ignore=tests/engine/,checking/test_schema.py scripting/test_fuzz.py \
                 reading/test_yaml_source.py)

# The tests' own set-up, not make run's: BehaviorTree.CPP and the interop tests' checker,
# built from the ROS overlay's sources once per machine (cached in ~/.cache/sar_framework;
# minutes the first time, a second after). No test builds it; without cmake or g++ this
# says so and the tests that need it skip, with that reason.
test-setup: setup  ## what the tests need besides .venv: the BehaviorTree.CPP checker
	@$(BIN)/python tests/interop/btcpp_build.py

test: setup lint test-setup  ## ruff + the whole test suite (+ engine tests on py_trees 2.2.3)
	@log=$$(mktemp); nice -n 5 $(COMPAT_BIN)/python -m pytest -q -p no:cacheprovider \
	  tests/engine $(NO_PY_TREES) > $$log 2>&1 & compat=$$!; \
	  trap 'rm -f $$log' EXIT; trap 'kill $$compat 2>/dev/null; exit 130' INT TERM; \
	  $(BIN)/python -m pytest -q -p no:cacheprovider $(XDIST); rc=$$?; \
	  [ $$rc -ne 5 ] || echo "make test: pytest collected no tests" >&2; \
	  wait $$compat; compat_rc=$$?; \
	  echo "engine tests on py_trees 2.2.3 (.venv-compat; ran alongside, at nice 5):"; \
	  cat $$log; [ $$compat_rc -ne 5 ] || echo "make test: no engine tests collected" >&2; \
	  [ $$rc -ne 0 ] && exit $$rc; exit $$compat_rc

test-fast: setup test-setup  ## tests without the slow end-to-end runs
	@$(BIN)/python -m pytest -q -p no:cacheprovider $(XDIST) -m "not slow"

lint: setup  ## ruff check
	@$(BIN)/ruff check sar_framework plugins tests benchmarks tools launch

bench: setup  ## every benchmark table
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

clean:  ## remove the venvs and build output
	rm -rf $(VENV) .venv-compat build .pytest_cache .ruff_cache
