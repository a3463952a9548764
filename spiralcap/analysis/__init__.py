"""Application-level analyses that combine the domain packages for the CLI and the report.

Each returns frozen dataclasses; ``spiralcap.commands`` prints them and the report reads them,
so neither imports the other.
"""
