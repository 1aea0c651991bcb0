"""Pipeline: see DESIGN.md (Layout)."""
