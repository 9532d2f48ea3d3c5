"""Behavior-tree XML as plain elements, read defensively (defusedxml: no DTD, no entities, limits): the XML
layer under bt.parse (the one parser of the tree language: check, simulator, exporters and verifier read its
typed tree) and what exporters write v4 files from."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from defusedxml import DefusedXmlException
from defusedxml.ElementTree import DefusedXMLParser

from socnavgen.errors import ValidationFailed

MAX_XML_BYTES = 256 * 1024
MAX_DEPTH = 64
MAX_ELEMENTS = 5000


@dataclass
class BTElement:
    """One XML element: tag, attributes, children, and its line in the source (for messages)."""

    tag: str
    attrs: dict[str, str]
    children: list[BTElement] = field(default_factory=list)
    line: int | None = None

    def walk(self):  # noqa: ANN201 - generator of BTElement
        yield self
        for child in self.children:
            yield from child.walk()


class _LineTreeBuilder(ET.TreeBuilder):
    def __init__(self) -> None:
        super().__init__()
        self.parser: DefusedXMLParser | None = None
        self.lines: dict[int, int] = {}
        self.count = 0
        self.depth = 0

    def start(self, tag, attrs):  # noqa: ANN001, ANN201 - ElementTree API
        self.count += 1
        self.depth += 1
        if self.count > MAX_ELEMENTS:
            raise ValidationFailed(f"tree has more than {MAX_ELEMENTS} elements")
        if self.depth > MAX_DEPTH:
            raise ValidationFailed(f"tree is nested more than {MAX_DEPTH} levels deep")
        elem = super().start(tag, attrs)
        if self.parser is not None:
            self.lines[id(elem)] = self.parser.parser.CurrentLineNumber
        return elem

    def end(self, tag):  # noqa: ANN001, ANN201
        self.depth -= 1
        return super().end(tag)


def read_xml(text: str, source: str = "<string>", tag: str | None = "root") -> BTElement:
    """The XML's top element (which must be <`tag`> unless `tag` is None). Raises ValidationFailed (with
    source and line) on anything hostile or malformed."""
    if len(text.encode("utf-8", errors="ignore")) > MAX_XML_BYTES:
        raise ValidationFailed(f"XML is larger than {MAX_XML_BYTES} bytes", file=source)
    builder = _LineTreeBuilder()
    parser = DefusedXMLParser(target=builder, forbid_dtd=True, forbid_entities=True, forbid_external=True)
    builder.parser = parser
    try:
        parser.feed(text)
        top = parser.close()
    except ValidationFailed as exc:
        raise ValidationFailed(exc.message, file=source) from exc
    except DefusedXmlException as exc:
        raise ValidationFailed(f"forbidden XML construct ({type(exc).__name__}): DTDs and entities are not allowed",
                               file=source) from exc
    except ET.ParseError as exc:
        line = exc.position[0] if exc.position else None
        raise ValidationFailed(f"XML does not parse: {exc}", file=source, line=line) from exc

    def convert(e: ET.Element) -> BTElement:
        return BTElement(tag=e.tag, attrs=dict(e.attrib), children=[convert(c) for c in e],
                         line=builder.lines.get(id(e)))

    root = convert(top)
    if tag is not None and root.tag != tag:
        raise ValidationFailed(f"the top element is <{root.tag}>, expected <{tag}>", file=source, line=root.line)
    return root
