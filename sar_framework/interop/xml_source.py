"""Read an XML file into a small element tree that remembers where each element starts.

``xml.etree`` drops line numbers; the standard library's expat parser reports them, so
this builds the few facts the importer needs (tag, attributes, children, text, line,
column) with it. Document type declarations (and so entity definitions) are refused.

BehaviorTree.CPP reads files with tinyxml2, which accepts two things XML does not, and
so does this reader: a raw ``<`` inside an attribute value (scripts such as
``_skipIf="count < 3"``), and anything after the root element (tinyxml2 keeps it;
BT.CPP reads only the first element, ``RootElement()``).
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
        severity: ``error`` (the input cannot be read so) or ``warning`` (it is, but
            look).
    """

    file: str
    line: int
    column: int
    message: str
    severity: str = "error"

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.column}: {self.severity}: {self.message}"


@dataclass
class Element:
    """One XML element.

    Attributes:
        tag: The element name.
        attrs: The attributes, in document order.
        children: The child elements (comments are dropped).
        line: 1-based line of the start tag.
        column: 1-based column of the start tag.
        text: The character data directly inside the element.
    """

    tag: str
    attrs: dict[str, str]
    line: int
    column: int
    children: list[Element] = field(default_factory=list)
    text: str = ""


class XmlError(Exception):
    """The file is not well-formed XML (or declares a DOCTYPE); carries the problem."""

    def __init__(self, problem: Problem) -> None:
        super().__init__(str(problem))
        self.problem = problem


#: Stands for a raw ``<`` inside an attribute value while expat reads the text.
_LESS_THAN = "\ue000"


def _quote_attribute_less_thans(text: str) -> str:
    """Replace every ``<`` inside a quoted attribute value (inside a tag) by a stand-in."""
    out: list[str] = []
    in_tag = False
    quote = ""
    index = 0
    while index < len(text):
        char = text[index]
        if text.startswith("<!--", index) and not in_tag:
            end = text.find("-->", index)
            end = len(text) if end < 0 else end + 3
            out.append(text[index:end])
            index = end
            continue
        if quote:
            out.append(_LESS_THAN if char == "<" else char)
            quote = "" if char == quote else quote
        elif in_tag:
            out.append(char)
            if char in "\"'":
                quote = char
            elif char == ">":
                in_tag = False
        else:
            out.append(char)
            in_tag = char == "<"
        index += 1
    return "".join(out)


def _parse(text: str, file: str) -> Element:
    parser = expat.ParserCreate()
    stack: list[Element] = []
    roots: list[Element] = []

    def start(tag: str, attrs: dict[str, str]) -> None:
        attrs = {k: v.replace(_LESS_THAN, "<") for k, v in attrs.items()}
        element = Element(tag, attrs, parser.CurrentLineNumber, parser.CurrentColumnNumber + 1)
        (stack[-1].children if stack else roots).append(element)
        stack.append(element)

    def end(_tag: str) -> None:
        stack.pop()

    def characters(data: str) -> None:
        if stack:
            stack[-1].text += data

    def doctype(*_args: object) -> None:
        raise XmlError(Problem(file, parser.CurrentLineNumber, parser.CurrentColumnNumber + 1,
                               "a DOCTYPE is not accepted in BehaviorTree.CPP XML"))

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = characters
    parser.StartDoctypeDeclHandler = doctype
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        if exc.code == expat.errors.codes[expat.errors.XML_ERROR_JUNK_AFTER_DOC_ELEMENT] \
                and roots and not stack:
            return roots[0]  # tinyxml2 keeps what follows; BT.CPP reads the first element
        message = expat.ErrorString(exc.code)
        raise XmlError(Problem(file, exc.lineno, exc.offset + 1, f"XML: {message}")) from None
    return roots[0]


def parse_xml(text: str | bytes, file: str) -> Element:
    """Parse an XML document as BehaviorTree.CPP's tinyxml2 reads it.

    Args:
        text: The document.
        file: Its name, for problems.

    Returns:
        The root element.

    Raises:
        XmlError: Not well-formed (beyond what tinyxml2 forgives), or with a document
            type declaration.
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8-sig")
    try:
        return _parse(text, file)
    except XmlError as first:
        lenient = _quote_attribute_less_thans(text)
        if lenient == text:
            raise
        try:
            return _parse(lenient, file)
        except XmlError:
            raise first from None


def read_xml(path: str | Path) -> Element:
    """Parse the XML file at ``path`` (problems name it as given)."""
    return parse_xml(Path(path).read_bytes(), str(path))
