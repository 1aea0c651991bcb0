"""Structure: see DESIGN.md (Layout)."""
