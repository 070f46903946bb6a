"""Proving years later what was tested: BagIt bags of a campaign and the catalog of them."""
