"""An independent drop simulator and the truth forms of certkit's blind check (issue 14):
written apart from certkit's force laws; it imports nothing from certkit."""

from .forms import FORMS, Form, Truth
from .simulator import Gear, Nuisances, Record, simulate

__all__ = ["FORMS", "Form", "Gear", "Nuisances", "Record", "Truth", "simulate"]
