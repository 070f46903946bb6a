"""Writes ``spec-reference.md``, the campaign spec reference, from certkit's own JSON Schema
(:func:`certkit.spec.schema.json_schema`, what ``certkit schema`` prints) each time the
site is built, so that the reference cannot drift from the loader.  The generated page is
not committed (``.gitignore``)."""

from __future__ import annotations

import json
import re
import typing
from generated_page import register

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
    if inner.get("type") == "object" and "$ref" in inner.get("additionalProperties", {}):
        return "a mapping", inner["additionalProperties"]["$ref"].rsplit("/", 1)[1], False
    if inner.get("type") == "array":
        items = inner.get("items", {})
        if "$ref" in items:
            return "a list of blocks", items["$ref"].rsplit("/", 1)[1], True
        if "oneOf" in items and all("$ref" in c for c in items["oneOf"]):
            return "a list of blocks", items["oneOf"][0]["$ref"].rsplit("/", 1)[1], True
        what, _, _ = _kind(items, defs)
        return f"a list, each {what}", None, False
    if "const" in inner:
        return f"`{inner['const']}`", None, False
    if "enum" in inner:
        return "one of " + ", ".join(f"`{v}`" for v in inner["enum"]), None, False
    if inner.get("format") == "date":
        return "a date, `YYYY-MM-DD`", None, False
    # the description of an optional key's one choice is its type's (the key's own sits
    # beside the anyOf)
    if _describes_a_value(inner.get("description")) or (inner is not node
                                                        and inner.get("description")):
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
        mark in text for mark in ("e.g.", "with its unit", "percentage", "a unit of"))


def _default(node: dict, required: bool) -> str:
    if required:
        return "required"
    default = node.get("default")
    if isinstance(default, dict) and "text" in default:
        return f"default `{default['text']}`"      # a typed value: as the user writes it
    if isinstance(default, dict):
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


def _model_in(annotation):
    """The pydantic model an annotation holds (``X``, ``X | None``, ``list[X]``,
    ``dict[str, X]``, a union of models: its first), or None."""
    from pydantic import BaseModel

    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for argument in typing.get_args(annotation):
        found = _model_in(argument)
        if found is not None:
            return found
    return None


def _value_kind(field, defs: dict) -> str | None:
    """What to write for a key whose own description hides its type's in the schema (a
    weight with a note of its own): the type's schema, asked of pydantic alone."""
    from pydantic import TypeAdapter

    annotation = (typing.Annotated[field.annotation, *field.metadata] if field.metadata
                  else field.annotation)
    try:
        alone = TypeAdapter(annotation).json_schema()
    except Exception:            # a type pydantic cannot describe alone: keep the schema's
        return None
    what, ref, _ = _kind(alone, alone.get("$defs", defs))
    return None if ref is not None else what


def reference(schema: dict, model) -> str:
    """The reference page of ``schema``, the JSON Schema of the pydantic ``model``."""
    defs = schema.get("$defs", {})
    lines = [HEAD]
    queue = [("(top level)", schema, model)]
    seen: set[str] = set()
    while queue:
        path, block, model = queue.pop(0)
        properties = block.get("properties", {})
        required = set(block.get("required", []))
        lines += ["", f"({_label(path)})=", f"## `{path}`" if path != "(top level)"
                  else "## The top level", ""]
        if path != "(top level)" and block.get("description"):
            lines += [_cell(block["description"]), ""]
        lines += ["| key | what to write | required / default | meaning |",
                  "|---|---|---|---|"]
        for name, node in properties.items():
            field = model.model_fields[name] if model is not None else None
            what, ref, is_list = _kind(node, defs)
            if ref is None and field is not None and field.description and \
                    what in ("text", "a number or text", "a value"):
                what = _value_kind(field, defs) or what
            if ref is not None:
                child = f"{name}[]" if is_list else (f"{name}.ID" if what == "a mapping"
                                                     else name)
                child = child if path == "(top level)" else f"{path}.{child}"
                kind = {"a mapping": "a mapping from an id to a block",
                        "a list of blocks": "a list of blocks"}.get(what, "a block")
                what = f"[{kind}](#{_label(child)})"
            lines.append(f"| `{name}` | {_cell(what)} | {_default(node, name in required)} "
                         f"| {_cell(_meaning(name, node, defs))} |")
            if ref is not None and child not in seen:
                seen.add(child)
                variants = _variants(node)
                child_block = dict(defs[ref])
                if variants:
                    child_block["description"] = (
                        f"One block per `{variants[0]}`: " + ", ".join(
                            f"`{v}`" for v in variants[1]) + ". The keys are the same for each "
                        "(shown here for the first).")
                queue.append((child, child_block,
                              _model_in(field.annotation) if field is not None else None))
    return "\n".join(lines) + "\n"


def _variants(node: dict):
    """(discriminating key, its values) of a list of blocks told apart by one key, or None."""
    items = _optional_inner(node).get("items", {})
    discriminator = items.get("discriminator")
    if not discriminator:
        return None
    return discriminator["propertyName"], list(discriminator.get("mapping", {}))


def _page() -> str:
    from certkit.spec.schema import CampaignSpec, json_schema

    return reference(json_schema(), CampaignSpec)


def setup(app):
    return register(app, PAGE, _page)
