"""The sim-to-real gap: held-out drops, phases, residuals, attribution of the residual to an
unmodelled effect, the diagnosis itself and its blind check."""
