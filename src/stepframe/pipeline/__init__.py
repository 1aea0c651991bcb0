"""Pipeline: staged runs with a cache, record selection and reports (DESIGN.md, Layout).

Not built yet: the package exists so that the layout of DESIGN.md holds from the start.
"""
