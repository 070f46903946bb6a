"""Writes ``spec-reference.md``, the campaign spec reference, from certkit's own JSON Schema
(:func:`certkit.spec.schema.json_schema`, what ``certkit schema`` prints) each time the
site is built, so that the reference cannot drift from the loader.  The generated page is
not committed (``.gitignore``)."""

from __future__ import annotations

import json
import re
from pathlib import Path

PAGE = "spec-reference.md"
HEAD = """\
# Campaign spec reference

Every key certkit reads from a campaign spec, block by block, generated from the schema
certkit validates with (`certkit schema` prints it as JSON Schema for an editor). A key
shown *required* must be given; an optional key left out takes the default shown, or is
"not stated" (the report says so where it matters: see {doc}`campaign-spec`). A path such
as `gear_units[].strut` means the `strut` block of each entry of the `gear_units` list.
Keys not listed here are refused with the file, line and key named.
"""


def _label(path: str) -> str:
    """The anchor of a block's section (``gear_units[].strut`` -> ``spec-gear-units-strut``)."""
    return "spec-" + re.sub(r"[^a-z0-9]+", "-", path.lower()).strip("-")


def _cell(text: str) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _resolve(node: dict, defs: dict) -> dict:
    while "$ref" in node:
        node = defs[node["$ref"].rsplit("/", 1)[1]]
    return node


def _optional_inner(node: dict) -> dict:
    """The one non-null choice of an ``anyOf [X, null]`` (what an optional key holds)."""
    choices = [c for c in node.get("anyOf", []) if c.get("type") != "null"]
    return choices[0] if len(choices) == 1 else node


def _kind(node: dict, defs: dict) -> tuple[str, str | None, bool]:
    """(what to write, the block it opens or None, whether it is a list of that block)."""
    inner = _optional_inner(node)
    if "$ref" in inner:
        return "a block", inner["$ref"].rsplit("/", 1)[1], False
    if inner.get("type") == "array":
        items = inner.get("items", {})
        if "$ref" in items:
            return "a list of blocks", items["$ref"].rsplit("/", 1)[1], True
        what, _, _ = _kind(items, defs)
        return f"a list, each {what}", None, False
    if "const" in inner:
        return f"`{inner['const']}`", None, False
    if "enum" in inner:
        return "one of " + ", ".join(f"`{v}`" for v in inner["enum"]), None, False
    if inner.get("format") == "date":
        return "a date, `YYYY-MM-DD`", None, False
    if _describes_a_value(inner.get("description")):
        return inner["description"], None, False
    if "anyOf" in inner:
        parts = [_kind(c, defs)[0] for c in inner["anyOf"]]
        return " or ".join(parts), None, False
    return {"number": "a number", "integer": "an integer", "boolean": "`true` or `false`",
            "string": "text", "object": "a mapping"}.get(inner.get("type"), "a value"), None, \
        False


def _describes_a_value(text: str | None) -> bool:
    """Whether a schema description says what to write (a quantity type's "a length with
    its unit, e.g. '1 mm'") rather than what the key means."""
    return bool(text) and text.startswith(("a ", "an ")) and any(
        mark in text for mark in ("e.g.", "with its unit", "percentage"))


def _default(node: dict, required: bool) -> str:
    if required:
        return "required"
    if isinstance(node.get("default"), dict):
        return "optional (defaults in its block below)"
    if "default" not in node or node["default"] is None:
        return "optional"
    default = node["default"]
    if default in ([], {}):
        return "optional (empty)"
    return f"default `{json.dumps(default, ensure_ascii=False)}`"


def _meaning(name: str, node: dict, defs: dict) -> str:
    inner = _optional_inner(node)
    text = node.get("description")
    if _describes_a_value(text):
        text = None
    if text is None and "$ref" in inner:
        text = _resolve(inner, defs).get("description")
    return text or ""


def reference(schema: dict) -> str:
    defs = schema.get("$defs", {})
    lines = [HEAD]
    queue = [("(top level)", schema)]
    seen: set[str] = set()
    while queue:
        path, block = queue.pop(0)
        properties = block.get("properties", {})
        required = set(block.get("required", []))
        lines += ["", f"({_label(path)})=", f"## `{path}`" if path != "(top level)"
                  else "## The top level", ""]
        if path != "(top level)" and block.get("description"):
            lines += [_cell(block["description"]), ""]
        lines += ["| key | what to write | required / default | meaning |",
                  "|---|---|---|---|"]
        for name, node in properties.items():
            what, ref, is_list = _kind(node, defs)
            if ref is not None:
                child = f"{name}[]" if is_list else name
                child = child if path == "(top level)" else f"{path}.{child}"
                what = f"[{'a list of blocks' if is_list else 'a block'}](#{_label(child)})"
            lines.append(f"| `{name}` | {_cell(what)} | {_default(node, name in required)} "
                         f"| {_cell(_meaning(name, node, defs))} |")
            if ref is not None:
                if child not in seen:
                    seen.add(child)
                    queue.append((child, defs[ref]))
    return "\n".join(lines) + "\n"


def write(app) -> None:
    from certkit.spec.schema import json_schema

    text = reference(json_schema())
    target = Path(app.srcdir) / PAGE
    # rewritten only when it changed, so that an unchanged schema rebuilds nothing
    if not target.exists() or target.read_text(encoding="utf-8") != text:
        target.write_text(text, encoding="utf-8")


def setup(app):
    app.connect("builder-inited", write)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
