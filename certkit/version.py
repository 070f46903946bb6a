"""certkit's version: its one home, read by the package (``certkit.__version__``), by the
build (pyproject.toml's dynamic version) and by every record that names the software."""

VERSION = "0.1.0"
