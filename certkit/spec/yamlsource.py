"""Reading YAML while remembering on which line each key stands.

PyYAML's composer keeps a start mark on every node; walking the node tree once
gives a map from key paths (``("runs", 2, "drop_height")``) to 1-based line
numbers, used to point validation errors at the line the user must edit.
"""

from __future__ import annotations

from pathlib import Path

import yaml

from certkit.errors import CertkitInputError

LineMap = dict[tuple, int]


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys (a silently overwritten key is a typo), keys
    that are not text, sets (unordered) and aliases (&a/*a can expand without bound)."""

    def compose_node(self, parent, index):
        if self.check_event(yaml.events.AliasEvent):
            event = self.peek_event()
            raise yaml.composer.ComposerError(
                None, None, "YAML anchors and aliases (&name, *name) are not supported in a "
                            "campaign; write the values out", event.start_mark)
        return super().compose_node(parent, index)


def _refuse_set(loader, node):
    raise yaml.constructor.ConstructorError(
        None, None, "!!set is not supported (its order is undefined); write a list",
        node.start_mark)


def _construct_mapping(loader, node, deep=False):
    seen: dict = {}
    for key_node, _ in node.value:
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
_UniqueKeyLoader.add_constructor("tag:yaml.org,2002:set", _refuse_set)
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


def load_yaml(path: Path, display_name: str) -> tuple[object, LineMap]:
    """Load ``path`` as YAML, returning the data and its key-path -> line map."""
    try:
        content = path.read_bytes()
    except FileNotFoundError:
        raise CertkitInputError.single(display_name, None, "", "file not found") from None
    except IsADirectoryError:
        raise CertkitInputError.single(display_name, None, "", "is a folder, not a campaign "
                                                               "file") from None
    except OSError as exc:
        raise CertkitInputError.single(display_name, None, "", f"cannot read: {exc}") from None
    try:
        text = content.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = content[: exc.start].count(b"\n") + 1
        raise CertkitInputError.single(display_name, line, "", "not UTF-8 text (byte "
                                       f"0x{content[exc.start]:02x}); save the file as UTF-8") \
            from None
    lines: LineMap = {}
    try:
        node = yaml.compose(text, Loader=_UniqueKeyLoader)
        if node is not None:
            _walk(node, (), lines)
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - SafeLoader subclass
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = mark.line + 1 if mark else None
        raise CertkitInputError.single(
            display_name, line, "", f"not valid YAML: {exc.problem or exc}") from None
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
