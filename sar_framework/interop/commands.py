"""``sar-tree export`` and ``sar-tree import``: argument set-up and the work.

``sar_framework.cli`` registers these as subcommands. Exit codes follow the CLI's: 0
clean, 1 problems in the input (printed ``file:line:col: error: ...``), 2 usage errors.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

EXIT_OK, EXIT_ERRORS, EXIT_USAGE = 0, 1, 2


def _complain(text: str) -> None:
    sys.stderr.write(f"{text}\n")


def _input_file(path: str) -> bool:
    if not Path(path).is_file():
        _complain(f"sar-tree: error: no such file: '{path}'")
        return False
    return True


def _write(text: str, output: str | None) -> int:
    if output is None:
        sys.stdout.write(text)
        return EXIT_OK
    try:
        Path(output).write_text(text, encoding="utf-8")
    except OSError as exc:
        _complain(f"sar-tree: error: cannot write '{output}': {exc.strerror}")
        return EXIT_ERRORS
    return EXIT_OK


def _add_common(parser: argparse.ArgumentParser, what: str) -> None:
    parser.add_argument("-o", "--output", metavar="OUT", help=f"write the {what} to OUT, "
                        "not stdout")
    parser.add_argument("--plugin-path", action="append", default=[], metavar="P",
                        help="extra plugin .py file, directory or module name (repeatable)")


def configure_export(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree export``'s arguments."""
    parser.add_argument("tree", metavar="TREE", help="the tree file")
    parser.add_argument("--format", choices=("btcpp",), default="btcpp",
                        help="btcpp: BehaviorTree.CPP 4 XML with a TreeNodesModel (Groot2)")
    _add_common(parser, "XML")


def run_export(args: argparse.Namespace) -> int:
    """Validate a tree file and write it as BehaviorTree.CPP 4 XML."""
    from sar_framework.engine.api import validate
    from sar_framework.interop.btcpp_export import export_btcpp

    if not _input_file(args.tree):
        return EXIT_USAGE
    result = validate(args.tree, plugin_paths=args.plugin_path)
    for diagnostic in result.diagnostics:
        _complain(str(diagnostic))
    if result.spec is None or result.registry is None:
        if result.library is not None and not result.diagnostics:
            _complain(f"{args.tree}: a library of subtrees has no root to export")
        return EXIT_ERRORS
    folder = Path(args.output).resolve().parent if args.output else Path.cwd()
    extra = [str(Path(p).resolve()) if Path(p).exists() else p for p in args.plugin_path]
    try:
        text = export_btcpp(result.spec, result.registry, folder=folder, extra_plugins=extra)
    except ValueError as exc:  # a value BT.CPP's XML cannot carry, located
        _complain(str(exc))
        return EXIT_ERRORS
    return _write(text, args.output)


def _document_yaml(document: dict[str, Any], source: str) -> str:
    """Format an imported document as a tree file (block style, leaves on one line)."""
    import yaml

    header = f"# Imported from {source} by 'sar-tree import'.\n"
    return header + yaml.safe_dump(document, sort_keys=False, default_flow_style=None,
                                   allow_unicode=True, width=100)


def configure_import(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree import``'s arguments."""
    parser.add_argument("xml", metavar="FILE.xml", help="a BehaviorTree.CPP 4 XML file")
    parser.add_argument("--main", metavar="ID", help="the main tree, when the file has "
                        "several and no main_tree_to_execute")
    parser.add_argument("--nodes-model", action="append", default=[], metavar="FILE",
                        help="a palette whose <TreeNodesModel> declares the file's nodes "
                        "(e.g. Nav2's nav2_tree_nodes.xml; repeatable)")
    parser.add_argument("--scaffold", metavar="DIR", help="write a plugin module for the "
                        "leaves no plugin provides into DIR; the tree file names it")
    _add_common(parser, "tree file")


def _relative(path: str | Path, folder: Path) -> str:
    return os.path.relpath(Path(path).resolve(), folder) if Path(path).exists() else str(path)


def run_import(args: argparse.Namespace) -> int:
    """Convert BT.CPP 4 XML to a tree file, validated by our loader before it is written."""
    import tempfile

    from sar_framework.engine.api import validate
    from sar_framework.engine.diagnostics import did_you_mean
    from sar_framework.engine.registry import default_registry, extend
    from sar_framework.interop.btcpp_file import read_palette
    from sar_framework.interop.btcpp_import import import_btcpp
    from sar_framework.interop.btcpp_plugins import read_plugins
    from sar_framework.interop.btcpp_scaffold import scaffold_module
    from sar_framework.interop.xml_source import XmlError, read_xml

    if not _input_file(args.xml) or not all(_input_file(m) for m in args.nodes_model):
        return EXIT_USAGE
    models: dict = {}
    for palette in args.nodes_model:
        found, problems = read_palette(palette)
        models.update(found)
        for problem in problems:
            _complain(str(problem))
        if problems:
            return EXIT_ERRORS
    try:
        root = read_xml(args.xml)
    except XmlError as exc:
        _complain(str(exc.problem))
        return EXIT_ERRORS
    own, problems = read_plugins(root, args.xml)  # the file's own <Plugins>
    for problem in problems:
        _complain(str(problem))
    if problems:
        return EXIT_ERRORS
    registry = extend(default_registry().copy(), [*args.plugin_path, *own])
    result = import_btcpp(root, args.xml, registry, main=args.main, models=models)
    for problem in [*result.problems, *result.warnings]:
        _complain(str(problem))
    if result.document is None:
        return EXIT_ERRORS
    folder = Path(args.output).resolve().parent if args.output else Path.cwd()
    stem = Path(args.xml).stem.replace("-", "_").replace(".", "_")
    drafts = list(result.drafts.values())
    with tempfile.TemporaryDirectory() as scratch:
        plugins = [*own, *args.plugin_path]
        module: Path | None = None
        if drafts:
            module = Path(args.scaffold or scratch) / f"{stem}_leaves.py"
            text = scaffold_module(drafts, Path(args.xml).name)
            if module.exists() and module.read_text(encoding="utf-8") != text:
                _complain(f"sar-tree: error: {module} exists and differs from the scaffold "
                          "(it may hold your code): move it, or choose another --scaffold DIR")
                return EXIT_ERRORS
            module.parent.mkdir(parents=True, exist_ok=True)
            module.write_text(text, encoding="utf-8")
            if args.scaffold:
                plugins.append(str(module))
                _complain(f"{module}: scaffolded {len(drafts)} leaves: "
                          f"{', '.join(d.plugin for d in drafts)}")
            else:
                known = list(registry.names())  # a leaf's tag: the leaves it may mean
                for draft in (d for d in drafts if d.plugin == d.tag):
                    where = draft.where
                    _complain(f"{where.file}:{where.line}:{where.column}: warning: no plugin "
                              f"provides <{draft.tag}>{did_you_mean(draft.tag, known)}; "
                              "--scaffold DIR writes one to fill in")
        if plugins:
            entries = list(dict.fromkeys(_relative(p, folder) for p in plugins))
            result.document = {"format": 1, "plugins": entries,
                               **result.document}
        text = _document_yaml(result.document, Path(args.xml).name)
        check_paths = [str(module)] if module is not None and not args.scaffold else []
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", dir=folder, delete=False) as tmp:
            tmp.write(text)
        try:
            check = validate(tmp.name, plugin_paths=check_paths)
        finally:
            os.unlink(tmp.name)
    shown = args.output or "<stdout>"
    for diagnostic in check.diagnostics:
        _complain(str(diagnostic).replace(tmp.name, shown).replace(Path(tmp.name).name, shown))
    if check.spec is None:
        return EXIT_ERRORS
    return _write(text, args.output)


def configure_palette(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree palette``'s arguments."""
    _add_common(parser, "palette")
    parser.add_argument("--core", action="store_true",
                        help="start from the built-in kinds and leaves alone, not from every "
                        "installed plugin and app; add an app's leaves with --plugin-path")


def run_palette(args: argparse.Namespace) -> int:
    """Write the Groot2 ``<TreeNodesModel>`` of every registered leaf."""
    from sar_framework.engine.registry import core_registry, default_registry, extend
    from sar_framework.interop.btcpp_palette import palette_text

    base = core_registry() if args.core else default_registry().copy()
    registry = extend(base, args.plugin_path)
    for problem in registry.diagnostics:
        _complain(str(problem))
    if any(d.severity == "error" for d in registry.diagnostics):
        return EXIT_ERRORS
    return _write(palette_text(registry), args.output)
