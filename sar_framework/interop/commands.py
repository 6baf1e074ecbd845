"""``sar-tree export`` and ``sar-tree import``: argument set-up and the work.

``sar_framework.cli`` registers these as subcommands. Exit codes follow the CLI's: 0
clean, 1 problems in the input (printed ``file:line:col: error: ...``), 2 usage errors.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

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
    return _write(export_btcpp(result.spec, result.registry), args.output)


def configure_import(parser: argparse.ArgumentParser) -> None:
    """Add ``sar-tree import``'s arguments."""
    parser.add_argument("xml", metavar="FILE.xml", help="a BehaviorTree.CPP 4 XML file")
    _add_common(parser, "tree file")


def run_import(args: argparse.Namespace) -> int:
    """Convert BT.CPP 4 XML to a tree file, validated by our loader before it is written."""
    import tempfile

    from sar_framework.engine.api import validate
    from sar_framework.engine.registry import default_registry, extend
    from sar_framework.interop.btcpp_import import document_yaml, import_btcpp
    from sar_framework.interop.xml_source import XmlError, read_xml

    if not _input_file(args.xml):
        return EXIT_USAGE
    registry = extend(default_registry().copy(), args.plugin_path)
    try:
        result = import_btcpp(read_xml(args.xml), args.xml, registry)
    except XmlError as exc:
        _complain(str(exc.problem))
        return EXIT_ERRORS
    for problem in result.problems:
        _complain(str(problem))
    if result.document is None:
        return EXIT_ERRORS
    folder = Path(args.output).resolve().parent if args.output else Path.cwd()
    if args.plugin_path:
        result.document = {"format": 1, "plugins": [
            os.path.relpath(Path(p).resolve(), folder) if Path(p).exists() else p
            for p in args.plugin_path], **result.document}
    text = document_yaml(result.document, Path(args.xml).name)
    shown = args.output or "<stdout>"
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", dir=folder, delete=False) as tmp:
        tmp.write(text)
    try:
        check = validate(tmp.name)
    finally:
        os.unlink(tmp.name)
    for diagnostic in check.diagnostics:
        _complain(str(diagnostic).replace(tmp.name, shown).replace(Path(tmp.name).name, shown))
    if check.spec is None:
        return EXIT_ERRORS
    return _write(text, args.output)
