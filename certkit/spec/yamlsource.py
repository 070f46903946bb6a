"""Reading YAML while remembering on which line each key stands.

PyYAML's composer keeps a start mark on every node; walking the node tree once
gives a map from key paths (``("runs", 2, "drop_height")``) to 1-based line
numbers, used to point validation errors at the line the user must edit.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from certkit.errors import CertkitInputError, shown

LineMap = dict[tuple, int]


#: The largest spec file read [bytes]: the examples are 10-20 kB; PyYAML reads about a
#: megabyte a second, so a larger file is a wrong file named, not a campaign.
MAX_SPEC_BYTES = 2_000_000
#: The longest number a spec may hold, in characters: a float's 17 significant digits with
#: sign, point and exponent fit many times over; a longer one is a paste or a runaway key.
MAX_NUMBER = 40
_YAML_TAG = "tag:yaml.org,2002:"


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys (a silently overwritten key is a typo), keys
    that are not text, aliases (&a/*a can expand without bound), explicit tags (``!!int A``,
    ``!!set``: a campaign has no use for them, and PyYAML's constructors fail on many
    tagged values with errors of their own) and numbers longer than MAX_NUMBER."""

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.events.AliasEvent):
            raise yaml.composer.ComposerError(
                None, None, "YAML anchors and aliases (&name, *name) are not supported in a "
                            "campaign; write the values out", event.start_mark)
        tag = getattr(event, "tag", None)
        if tag is not None:
            written = "!!" + tag[len(_YAML_TAG):] if tag.startswith(_YAML_TAG) else tag
            raise yaml.composer.ComposerError(
                None, None, f"explicit YAML tags ({shown(written)}) are not supported in a "
                            f"campaign; write the value plainly (in quotes if it is text)",
                event.start_mark)
        return super().compose_node(parent, index)


def _construct_number(loader, node):
    """An int or a float as YAML 1.1 resolves it, bounded in length; text that matched the
    number pattern but is none (``0x_``) is an error at its line, not a crash."""
    if len(node.value) > MAX_NUMBER:
        raise yaml.constructor.ConstructorError(
            None, None, f"a number of {len(node.value)} characters is not a value a campaign "
                        f"holds (at most {MAX_NUMBER}); quote it if it is text",
            node.start_mark)
    constructor = (yaml.SafeLoader.construct_yaml_int if node.tag == _YAML_TAG + "int"
                   else yaml.SafeLoader.construct_yaml_float)
    try:
        return constructor(loader, node)
    except ValueError:
        raise yaml.constructor.ConstructorError(
            None, None, f"{shown(node.value)} is not a number; quote it if it is text",
            node.start_mark) from None


def _construct_mapping(loader, node, deep=False):
    seen: dict = {}
    for key_node, _ in node.value:
        if key_node.tag == _YAML_TAG + "merge":
            raise yaml.constructor.ConstructorError(
                None, None, "YAML merge keys (<<) are not supported in a campaign; write the "
                            "keys out", key_node.start_mark)
        key = loader.construct_object(key_node, deep=deep)
        if not isinstance(key, str):
            raise yaml.constructor.ConstructorError(
                None, None, f"key {key_node.value or '~'!r} is not a name; keys must be text",
                key_node.start_mark)
        if key in seen:
            raise yaml.constructor.ConstructorError(
                None, None, f"duplicate key {key!r} (first at line {seen[key] + 1})",
                key_node.start_mark)
        seen[key] = key_node.start_mark.line
    return yaml.SafeLoader.construct_mapping(loader, node, deep=deep)


_UniqueKeyLoader.add_constructor(
    yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)
_UniqueKeyLoader.add_constructor(_YAML_TAG + "int", _construct_number)
_UniqueKeyLoader.add_constructor(_YAML_TAG + "float", _construct_number)
# Dates stay text: the spec model parses them, so a malformed date gets our message.
_UniqueKeyLoader.yaml_implicit_resolvers = {
    first: [(tag, regexp) for tag, regexp in resolvers if tag != "tag:yaml.org,2002:timestamp"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}


def _walk(node, path: tuple, lines: LineMap) -> None:
    lines.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        for key_node, value_node in node.value:
            if not isinstance(key_node, yaml.ScalarNode):
                raise _ComplexKey(key_node.start_mark.line + 1)
            child = path + (key_node.value,)
            lines[child] = key_node.start_mark.line + 1
            _walk(value_node, child, lines)
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            _walk(item, path + (index,), lines)


class _ComplexKey(Exception):
    def __init__(self, line: int):
        self.line = line


def first_non_utf8(content: bytes) -> tuple[int, int] | None:
    """(line, byte value) of the first byte of ``content`` that is not UTF-8, or None when
    all of it is."""
    try:
        content.decode("utf-8")
    except UnicodeDecodeError as error:
        return content[:error.start].count(b"\n") + 1, content[error.start]
    return None


def load_yaml(path: Path, display_name: str) -> tuple[object, LineMap]:
    """Load ``path`` as YAML, returning the data and its key-path -> line map."""
    try:
        if path.exists() and not path.is_dir() and not path.is_file():
            raise CertkitInputError.single(display_name, None, "", "not a regular file (a pipe, "
                                                                   "socket or device)")
        if path.is_file() and path.stat().st_size > MAX_SPEC_BYTES:
            raise CertkitInputError.single(
                display_name, None, "", f"{path.stat().st_size} bytes is not a campaign spec "
                                        f"(at most {MAX_SPEC_BYTES}); check the file named")
        content = path.read_bytes()
    except FileNotFoundError:
        raise CertkitInputError.single(display_name, None, "", "file not found") from None
    except IsADirectoryError:
        raise CertkitInputError.single(display_name, None, "", "is a folder, not a campaign "
                                                               "file") from None
    except OSError as exc:
        raise CertkitInputError.single(display_name, None, "", f"cannot read: {exc}") from None
    first = first_non_utf8(content)
    if first is not None:
        line, byte = first
        raise CertkitInputError.single(display_name, line, "", f"not UTF-8 text (byte "
                                                               f"0x{byte:02x}); save the file "
                                                               f"as UTF-8")
    text = content.decode("utf-8")
    lines: LineMap = {}
    try:
        node = yaml.compose(text, Loader=_UniqueKeyLoader)
        if node is not None:
            _walk(node, (), lines)
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - SafeLoader subclass
    except yaml.reader.ReaderError as exc:  # a character YAML does not allow, e.g. a control one
        line = text[: exc.position].count("\n") + 1
        code = exc.character if isinstance(exc.character, int) else ord(exc.character)
        raise CertkitInputError.single(
            display_name, line, "", f"not valid YAML: a control character (U+{code:04X}) "
                                    f"stands in the text; delete it") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        line = mark.line + 1 if mark else None
        problem = getattr(exc, "problem", None) or str(exc)
        raise CertkitInputError.single(display_name, line, "",
                                       f"not valid YAML: {problem}") from None
    except RecursionError:
        raise CertkitInputError.single(display_name, None, "",
                                       "the YAML is nested too deeply") from None
    except _ComplexKey as error:
        raise CertkitInputError.single(display_name, error.line, "",
                                       "a key must be a plain name, not a list or a "
                                       "mapping") from None
    return data, lines


def line_of(lines: LineMap, location: tuple) -> int | None:
    """Line of the deepest existing prefix of ``location`` (a missing key points at its parent)."""
    for end in range(len(location), -1, -1):
        line = lines.get(tuple(location[:end]))
        if line is not None:
            return line
    return None
