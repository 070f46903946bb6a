"""``python -m certkit.cli``: the console entry point."""

from certkit.cli.app import run

run()
