"""The ``sar-tree`` command line.

Subcommands: validate | render | plugins | schema | run | export | import | palette |
replay | watch | studio.

Each subcommand is a :class:`Command` (its arguments and a function returning the
exit code) registered in :data:`_COMMANDS`; each imports what it needs inside its
functions, and only the subcommand named on the command line is set up, so
``sar-tree validate`` imports neither the runner nor graphviz.

Exit codes: 0 clean, 1 errors in the input (printed GCC style), 2 usage errors.
No traceback is ever printed unless ``--debug`` is given.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

from sar_framework.interop import commands as interop

EXIT_OK = 0
EXIT_ERRORS = 1
EXIT_USAGE = 2


class UsageError(Exception):
    """A bad command line: printed with the usage hint, exit code 2."""


@dataclass(frozen=True)
class Command:
    """One subcommand.

    Attributes:
        name: The subcommand's name.
        help: One line for ``sar-tree --help``.
        configure: Adds the subcommand's arguments to its parser.
        run: Does the work; returns the exit code.
    """

    name: str
    help: str
    configure: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


def _say(text: str, stream: TextIO | None = None) -> None:
    """Write one line to stdout (or ``stream``)."""
    (stream if stream is not None else sys.stdout).write(f"{text}\n")


def _complain(text: str) -> None:
    """Write one line to stderr."""
    sys.stderr.write(f"{text}\n")


def _print_diagnostics(diagnostics: Sequence[Any]) -> int:
    """Print diagnostics GCC style to stderr; return how many are errors."""
    for d in diagnostics:
        _complain(str(d))
    return sum(1 for d in diagnostics if d.severity == "error")


def _add_plugin_path(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--plugin-path",
        action="append",
        default=[],
        metavar="P",
        help="extra plugin .py file, directory or module name (repeatable)",
    )


def _check_tree_paths(paths: Sequence[str]) -> None:
    for path in paths:
        p = Path(path)
        if not p.exists():
            raise UsageError(f"no such file: '{path}'")
        if not p.is_file():
            raise UsageError(f"not a file: '{path}'")


# -- validate ---------------------------------------------------------------------------
def _configure_validate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("trees", nargs="+", metavar="TREE", help="tree files to check")
    _add_plugin_path(parser)
    parser.add_argument("-q", "--quiet", action="store_true", help="print only problems")


def _run_validate(args: argparse.Namespace) -> int:
    from sar_framework.engine.api import validate

    _check_tree_paths(args.trees)
    errors = 0
    for tree in args.trees:
        result = validate(tree, plugin_paths=args.plugin_path)
        count = _print_diagnostics(result.diagnostics)
        errors += count
        if args.quiet or count:
            continue
        if result.spec is not None:
            from sar_framework.mission.completion import resolve_completion

            completion, why = resolve_completion("auto", result.spec)
            source = "" if why.startswith("default") else ", declared in the tree file"
            _say(f"{tree}: ok ({len(result.spec)} nodes; completion: {completion}{source})")
        elif result.library is not None:
            _say(f"{tree}: ok (subtrees only: {result.library})")
    if errors:
        _complain(f"{errors} error{'s' if errors != 1 else ''}")
    return EXIT_ERRORS if errors else EXIT_OK


# -- render -----------------------------------------------------------------------------
def _configure_render(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("tree", metavar="TREE", help="the tree file")
    target = parser.add_mutually_exclusive_group()
    target.add_argument(
        "-o", "--output", metavar="OUT", help="write an image; format from the extension "
        "(.svg, .png, .pdf, .dot)"
    )
    target.add_argument(
        "--format", choices=("ascii", "unicode"), help="print the tree as text (default: unicode)"
    )
    parser.add_argument(
        "--all-params", action="store_true",
        help="show every leaf param, defaults included (default: only those the tree sets)",
    )
    parser.add_argument(
        "--data-edges", action="store_true",
        help="draw data edges: dotted, from the node writing a blackboard entry to each "
        "node reading it, labelled with the entry",
    )
    _add_plugin_path(parser)


def _run_render(args: argparse.Namespace) -> int:
    from sar_framework.engine.api import validate

    _check_tree_paths([args.tree])
    result = validate(args.tree, plugin_paths=args.plugin_path)
    if result.spec is None:
        _print_diagnostics(result.diagnostics)
        return EXIT_ERRORS
    from sar_framework.engine.rendering import render  # lazy: graphviz only when rendering

    if args.output is None:
        sys.stdout.write(render.render_text(
            result.spec, unicode=args.format != "ascii", all_params=args.all_params
        ))
        return EXIT_OK
    try:
        written = render.render_to_file(result.spec, Path(args.output), all_params=args.all_params,
                                        data=args.data_edges)
    except ValueError as exc:
        raise UsageError(str(exc)) from exc
    except Exception as exc:  # graphviz missing, unwritable path, ...
        _complain(f"sar-tree: error: cannot render '{args.output}': {exc}")
        return EXIT_ERRORS
    _say(f"wrote {written}")
    return EXIT_OK


# -- plugins ----------------------------------------------------------------------------
def _configure_plugins(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="machine-readable output")
    parser.add_argument("--kinds", action="store_true",
                        help="list the node kinds instead: composites, decorators, BT.CPP's "
                        "and Nav2's nodes")
    _add_plugin_path(parser)


def _run_plugins(args: argparse.Namespace) -> int:
    from sar_framework.engine.registry import default_registry, extend
    from sar_framework.plugin_catalogue import param_text, plugin_info, port_text

    registry = extend(default_registry().copy(), args.plugin_path)
    if args.kinds:
        from sar_framework.plugin_catalogue import kind_lines

        for line in kind_lines(registry):
            _say(line)
        return EXIT_OK
    errors = _print_diagnostics(registry.diagnostics)
    if args.json:
        import json

        json.dump([plugin_info(p) for p in registry], sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        for plugin in registry:
            _say(f"{plugin.name}  [{plugin.source}]")
            if plugin.description:
                _say(f"    {plugin.description}")
            for param in plugin.params:
                _say(f"    - {param_text(param)}")
            for port in plugin.ports:
                _say(f"    - {port_text(port)}")
            if plugin.context:
                _say(f"    context: {', '.join(plugin.context)}")
        if not len(registry):
            _say("no plugins registered")
    return EXIT_ERRORS if errors else EXIT_OK


# -- schema -----------------------------------------------------------------------------
def _configure_schema(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-o", "--output", metavar="FILE", help="write to FILE, not stdout")
    _add_core(parser)
    _add_plugin_path(parser)


def _add_core(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--core", action="store_true",
                        help="start from the built-in kinds and leaves alone, not from every "
                        "installed plugin and app; add an app's leaves with --plugin-path "
                        "(e.g. --core --plugin-path sar_plugins.sar.leaves)")


def _run_schema(args: argparse.Namespace) -> int:
    from sar_framework.engine.checking.schema import schema_text
    from sar_framework.engine.registry import core_registry, default_registry, extend

    base = core_registry() if args.core else default_registry().copy()
    registry = extend(base, args.plugin_path)
    if _print_diagnostics(registry.diagnostics):
        return EXIT_ERRORS
    text = schema_text(registry)
    if args.output is None:
        sys.stdout.write(text)
        return EXIT_OK
    try:
        Path(args.output).write_text(text, encoding="utf-8")
    except OSError as exc:
        _complain(f"sar-tree: error: cannot write '{args.output}': {exc.strerror}")
        return EXIT_ERRORS
    return EXIT_OK


# -- run, faults, replay, watch: their modules are imported only when chosen ------------
def _lazy(module: str, configure: str, run: str) -> tuple[
        Callable[[argparse.ArgumentParser], None], Callable[[argparse.Namespace], int]]:
    """A subcommand's ``configure`` and ``run``, functions of ``module`` imported when called.

    Nothing of ROS is imported until a command that needs it runs.
    """

    def configure_command(parser: argparse.ArgumentParser) -> None:
        getattr(importlib.import_module(module), configure)(parser)

    def run_command(args: argparse.Namespace) -> int:
        return int(getattr(importlib.import_module(module), run)(args))

    return configure_command, run_command


def _configure_faults(parser: argparse.ArgumentParser) -> None:
    del parser  # no options


def _run_faults(args: argparse.Namespace) -> int:
    from sar_framework.orchestrate.faults import faults_table

    sys.stdout.write(faults_table())
    return EXIT_OK


_COMMANDS: dict[str, Command] = {
    c.name: c
    for c in (
        Command("validate", "check tree files; print problems as FILE:LINE:COL",
                _configure_validate, _run_validate),
        Command("render", "draw a tree (svg, png, pdf, dot) or print it as text",
                _configure_render, _run_render),
        Command("plugins", "list the registered leaf plugins and their params",
                _configure_plugins, _run_plugins),
        Command("schema", "print the JSON Schema of the tree format", _configure_schema,
                _run_schema),
        Command("run", "run a mission: simulator, servers and runner; print progress, "
                "write a report", *_lazy("sar_framework.orchestrate", "configure", "run_command")),
        Command("faults", "list the faults `run` can inject (parameters, units, meaning)",
                _configure_faults, _run_faults),
        Command("export", "write a tree as BehaviorTree.CPP 4 XML (Groot2 opens it)",
                interop.configure_export, interop.run_export),
        Command("import", "turn BehaviorTree.CPP 4 XML into a validated tree file",
                interop.configure_import, interop.run_import),
        Command("palette", "write a Groot2 <TreeNodesModel> of every node kind",
                interop.configure_palette, interop.run_palette),
        Command("replay", "draw a mission's report again from its recording (.mcap)",
                *_lazy("sar_framework.recording.replay", "configure", "replay_command")),
        Command("watch", "show the running mission's tree live in the terminal",
                *_lazy("sar_framework.watch.command", "configure", "watch_command")),
        Command("studio", "the mission in the browser: live, replayed from a recording, "
                "or a tree edited",
                *_lazy("sar_framework.studio.command", "configure", "studio_command")),
    )
}  # fmt: skip


def build_parser(argv: Sequence[str] | None = None) -> argparse.ArgumentParser:
    """Return the ``sar-tree`` argument parser.

    Args:
        argv: The arguments about to be parsed: only the subcommand their first word names
            is set up (so ``validate`` never imports what ``run`` needs). None: all.

    Returns:
        The parser.
    """
    first = next((a for a in argv if not a.startswith("-")), None) if argv is not None else None
    chosen = first if first in _COMMANDS else None
    parser = argparse.ArgumentParser(
        prog="sar-tree", description="Schema-checked YAML behaviour trees (py_trees)."
    )
    parser.add_argument("--debug", action="store_true", help="show tracebacks of internal errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for command in _COMMANDS.values() if chosen is None else [_COMMANDS[chosen]]:
        sub_parser = sub.add_parser(command.name, help=command.help, description=command.help)
        # `--debug` is accepted after the subcommand too (SUPPRESS keeps the global value).
        sub_parser.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                                help="show tracebacks of internal errors")
        if argv is None or chosen is not None:
            command.configure(sub_parser)
        sub_parser.set_defaults(_command=command)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line.

    Args:
        argv: Arguments without the program name; defaults to ``sys.argv[1:]``.

    Returns:
        The process exit code: 0 clean, 1 errors, 2 usage errors.
    """
    argv = sys.argv[1:] if argv is None else argv
    parser = build_parser(argv)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help (0) or a usage error (2)
        return exc.code if isinstance(exc.code, int) else EXIT_USAGE
    try:
        return args._command.run(args)
    except UsageError as exc:
        _complain(f"sar-tree: error: {exc}")
        return EXIT_USAGE
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # `sar-tree plugins | head`
        return EXIT_OK
    except Exception as exc:
        if args.debug:
            import traceback

            traceback.print_exc()
        _complain(
            f"sar-tree: internal error: {type(exc).__name__}: {exc}"
            + ("" if args.debug else " (run with --debug for a traceback)")
        )
        return EXIT_ERRORS
