"""Writes ``cli.md``, the command-line reference, from certkit's command-line application
each time the site is built: every command's ``--help`` as certkit prints it, so that the
page cannot drift from the commands.  The generated page is not committed."""

from __future__ import annotations

from generated_page import register

PAGE = "cli.md"
HEAD = """\
# Command-line reference

Every command and option, as `certkit COMMAND --help` prints them (generated from the
commands themselves when this site was built). Exit codes and what each means:
{doc}`robustness`.
"""
WIDTH = 88


def _commands(group, path):
    """(path, command) of every command under ``group``, depth first, in listing order."""
    for name in group.list_commands(None):
        command = group.get_command(None, name)
        yield [*path, name], command
        if hasattr(command, "list_commands"):
            yield from _commands(command, [*path, name])


def reference() -> str:
    import typer

    import certkit.cli  # noqa: F401  (registers every command on the application)
    from certkit.cli.app import app

    root = typer.main.get_command(app)
    sections = [HEAD, "## `certkit`", "", "```text", _help(root, ["certkit"]), "```"]
    for path, command in _commands(root, ["certkit"]):
        sections += ["", f"## `{' '.join(path)}`", "", "```text", _help(command, path), "```"]
    return "\n".join(sections) + "\n"


def _help(command, path) -> str:
    import click as _unused  # noqa: F401  (typer's click is its own; the context is typer's)

    context = command.context_class(command, info_name=" ".join(path),
                                    terminal_width=WIDTH, max_content_width=WIDTH)
    return command.get_help(context).rstrip()


def setup(app):
    return register(app, PAGE, reference)
