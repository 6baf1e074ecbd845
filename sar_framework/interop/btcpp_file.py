"""The shape of a BehaviorTree.CPP 4 file, read as BT.CPP 4.7's ``XMLParser`` reads it.

* ``<root>`` holds any number of ``<BehaviorTree ID="...">`` (a tree without ``ID`` is
  ``BehaviorTree_N``, as BT.CPP names it, and is refused when there are several, as BT.CPP
  refuses it), at most one ``<TreeNodesModel>`` and any ``<include path="..."/>``.
* ``BTCPP_format`` may be absent (BT.CPP only warns); ``"4"`` is read; any other value is
  refused (v3 files differ: use BT.CPP's ``convert_v3_to_v4`` script first).
* The main tree is ``main_tree_to_execute`` of the first file, else the one the caller
  names, else the only tree; otherwise the problem lists the IDs.
* ``<include path="...">`` is read relative to the including file (BT.CPP:
  ``current_path``); ``ros_pkg="P"`` makes it relative to ``share/P`` under
  ``$AMENT_PREFIX_PATH``, as ``ament_index_cpp`` would find it.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from sar_framework.interop.btcpp_blackboard import DECLARATIONS_TAG
from sar_framework.interop.btcpp_models import NodeModel, read_models
from sar_framework.interop.btcpp_plugins import PLUGINS_TAG
from sar_framework.interop.xml_source import Element, Problem, XmlError, read_xml


@dataclass(frozen=True)
class TreeSource:
    """One ``<BehaviorTree>``: its element and the file it is in."""

    element: Element
    file: str


@dataclass
class BtcppFile:
    """Every tree and model of a file and its includes.

    Attributes:
        trees: Tree ID -> where it is, in document order (includes first, as BT.CPP).
        main: The main tree's ID, or None when it cannot be told (see problems).
        models: Node ID -> model, from the files' ``<TreeNodesModel>``.
        declarations: Tree ID -> its ``<Blackboard>`` element (our export's declarations
            of that tree's ``blackboard:`` section; BT.CPP ignores it).
        problems: Every problem, in reading order.
    """

    trees: dict[str, TreeSource] = field(default_factory=dict)
    main: str | None = None
    models: dict[str, NodeModel] = field(default_factory=dict)
    declarations: dict[str, Element] = field(default_factory=dict)
    problems: list[Problem] = field(default_factory=list)


def _at(file: str, element: Element, message: str) -> Problem:
    return Problem(file, element.line, element.column, message)


def _ros_share(package: str) -> Path | None:
    for prefix in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep):
        share = Path(prefix) / "share" / package
        if prefix and share.is_dir():
            return share
    return None


class _Reader:
    def __init__(self) -> None:
        self.result = BtcppFile()
        self.opened: set[Path] = set()
        self.unnamed = 0

    def read(self, root: Element, file: str) -> None:
        if root.tag != "root":
            self.result.problems.append(_at(file, root, f"expected <root>, got <{root.tag}> "
                                            "(BT.CPP: 'The XML must have a root node "
                                            "called <root>')"))
            return
        version = root.attrs.get("BTCPP_format")
        if version is not None and version.strip() != "4":
            self.result.problems.append(_at(file, root, f"BTCPP_format=\"{version}\": only "
                                            "BehaviorTree.CPP 4 files are read (convert a v3 "
                                            "file with BT.CPP's convert_v3_to_v4.py first)"))
            return
        for element in root.children:
            if element.tag == "include":
                self.include(element, file)
        models = [e for e in root.children if e.tag == "TreeNodesModel"]
        for extra in models[1:]:
            self.result.problems.append(_at(file, extra, "a second <TreeNodesModel> (BT.CPP: "
                                            "'Only a single node <TreeNodesModel> is "
                                            "supported')"))
        if models:
            self.add_models(models[0], file)
        trees = [e for e in root.children if e.tag == "BehaviorTree"]
        for element in trees:
            tree_id = element.attrs.get("ID")
            if not tree_id:
                if len(root.children) > 1:
                    self.result.problems.append(_at(file, element, "<BehaviorTree> needs an "
                                                    "ID when the file holds other elements "
                                                    "(BT.CPP refuses it)"))
                    continue
                tree_id = f"BehaviorTree_{self.unnamed}"
                self.unnamed += 1
            if tree_id in self.result.trees:
                first = self.result.trees[tree_id]
                self.result.problems.append(_at(file, element, f"a second <BehaviorTree ID=\""
                                                f"{tree_id}\"> (the first is at "
                                                f"{first.file}:{first.element.line}); BT.CPP "
                                                "would silently keep this one"))
            self.result.trees[tree_id] = TreeSource(element, file)
        for element in root.children:
            if element.tag == DECLARATIONS_TAG and element.attrs.get("ID"):
                self.result.declarations[element.attrs["ID"]] = element
            elif element.tag not in ("include", "TreeNodesModel", "BehaviorTree", PLUGINS_TAG):
                self.result.problems.append(_at(file, element, f"unexpected <{element.tag}> "
                                                "under <root> (BT.CPP reads only "
                                                "<BehaviorTree>, <TreeNodesModel> and "
                                                "<include>; ours also <Blackboard ID=...> "
                                                "and <Plugins>)"))

    def add_models(self, element: Element, file: str) -> None:
        models, problems = read_models(element, file)
        self.result.models.update(models)
        self.result.problems.extend(problems)

    def include(self, element: Element, file: str) -> None:
        text = element.attrs.get("path")
        if not text:
            self.result.problems.append(_at(file, element, "<include> needs a path (BT.CPP: "
                                            "'Invalid <include> tag: missing 'path' "
                                            "attribute')"))
            return
        path = Path(text)
        package = element.attrs.get("ros_pkg")
        if package and not path.is_absolute():
            share = _ros_share(package)
            if share is None:
                self.result.problems.append(_at(file, element, f"<include ros_pkg=\"{package}"
                                                "\">: no share/" + package + " under "
                                                "$AMENT_PREFIX_PATH (source the ROS workspace "
                                                "that installs it)"))
                return
            path = share / path
        if not path.is_absolute():
            path = Path(file).resolve().parent / path
        resolved = path.resolve()
        if resolved in self.opened:
            self.result.problems.append(_at(file, element, f"<include path=\"{text}\"> "
                                            "includes a file already read (a cycle)"))
            return
        if not resolved.is_file():
            self.result.problems.append(_at(file, element, f"<include path=\"{text}\">: no "
                                            f"such file ({path})"))
            return
        self.opened.add(resolved)
        try:
            root = read_xml(path)
        except XmlError as exc:
            self.result.problems.append(exc.problem)
            return
        self.read(root, str(path))


def read_btcpp(root: Element, file: str, *, main: str | None = None,
               models: dict[str, NodeModel] | None = None) -> BtcppFile:
    """Collect the trees and models of a parsed BT.CPP file and of what it includes.

    Args:
        root: The parsed ``<root>`` (:func:`.xml_source.read_xml`).
        file: Its file name (includes are found relative to it).
        main: The main tree the caller names (``--main``); the file's
            ``main_tree_to_execute`` comes first, as in BT.CPP.
        models: Node models read beforehand (``--nodes-model`` palettes); the file's own
            ``<TreeNodesModel>`` entries replace them.

    Returns:
        The trees, the main tree's ID, the models and the problems.
    """
    reader = _Reader()
    reader.result.models.update(models or {})
    reader.opened.add(Path(file).resolve())
    reader.read(root, file)
    result = reader.result
    named = root.attrs.get("main_tree_to_execute") if root.tag == "root" else None
    if named and main and named != main:
        result.problems.append(_at(file, root, f"--main {main}, but the file says "
                                   f"main_tree_to_execute=\"{named}\""))
    choice = named or main or (next(iter(result.trees)) if len(result.trees) == 1 else None)
    ids = ", ".join(result.trees) or "none"
    if choice is None and result.trees:
        result.problems.append(_at(file, root, f"which tree is the main one? the file has no "
                                   f"main_tree_to_execute; name one with --main (trees: "
                                   f"{ids})"))
    elif choice is None:
        result.problems.append(_at(file, root, "no <BehaviorTree> in the file"))
    elif choice not in result.trees:
        result.problems.append(_at(file, root, f"no <BehaviorTree ID=\"{choice}\"> (trees: "
                                   f"{ids})"))
    else:
        result.main = choice
    return result


def read_palette(path: str) -> tuple[dict[str, NodeModel], list[Problem]]:
    """Read the ``<TreeNodesModel>`` of a palette file (``--nodes-model``).

    Returns:
        ID -> model, and the problems (an unreadable file is one problem).
    """
    try:
        root = read_xml(path)
    except XmlError as exc:
        return {}, [exc.problem]
    models = [e for e in root.children if e.tag == "TreeNodesModel"]
    if root.tag == "TreeNodesModel":
        models = [root]
    if not models:
        return {}, [_at(path, root, "no <TreeNodesModel> in this file")]
    found: dict[str, NodeModel] = {}
    problems: list[Problem] = []
    for element in models:
        more, trouble = read_models(element, path)
        found.update(more)
        problems.extend(trouble)
    return found, problems
