"""Read an XML file into a small element tree that remembers where each element starts.

``xml.etree`` drops line numbers; the standard library's expat parser reports them, so
this builds the few facts the importer needs (tag, attributes, children, line, column)
with it. Document type declarations (and so entity definitions) are refused.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat


@dataclass(frozen=True)
class Problem:
    """One problem in an input file, printed GCC style (``file:line:col: error: text``).

    Attributes:
        file: The file, as the user named it.
        line: 1-based line.
        column: 1-based column.
        message: What is wrong, and what to do.
    """

    file: str
    line: int
    column: int
    message: str

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: error: {self.message}"


@dataclass
class Element:
    """One XML element.

    Attributes:
        tag: The element name.
        attrs: The attributes, in document order.
        children: The child elements (text and comments are dropped).
        line: 1-based line of the start tag.
        column: 1-based column of the start tag.
    """

    tag: str
    attrs: dict[str, str]
    line: int
    column: int
    children: list[Element] = field(default_factory=list)


class XmlError(Exception):
    """The file is not well-formed XML (or declares a DOCTYPE); carries the problem."""

    def __init__(self, problem: Problem) -> None:
        super().__init__(str(problem))
        self.problem = problem


def parse_xml(text: str | bytes, file: str) -> Element:
    """Parse an XML document.

    Args:
        text: The document.
        file: Its name, for problems.

    Returns:
        The root element.

    Raises:
        XmlError: Not well-formed, or with a document type declaration.
    """
    parser = expat.ParserCreate()
    stack: list[Element] = []
    roots: list[Element] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        element = Element(tag, attrs, parser.CurrentLineNumber, parser.CurrentColumnNumber + 1)
        (stack[-1].children if stack else roots).append(element)
        stack.append(element)

    def end(_tag: str) -> None:
        stack.pop()

    def doctype(*_args: object) -> None:
        raise XmlError(Problem(file, parser.CurrentLineNumber, parser.CurrentColumnNumber + 1,
                               "a DOCTYPE is not accepted in BehaviorTree.CPP XML"))

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.StartDoctypeDeclHandler = doctype
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        message = expat.ErrorString(exc.code)
        raise XmlError(Problem(file, exc.lineno, exc.offset + 1, f"XML: {message}")) from None
    return roots[0]


def read_xml(path: str | Path) -> Element:
    """Parse the XML file at ``path`` (problems name it as given)."""
    return parse_xml(Path(path).read_bytes(), str(path))
