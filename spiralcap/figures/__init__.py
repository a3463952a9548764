"""Figures: matplotlib lives here and in ``spiralcap.report`` only.

Every plotting function takes ``ax=`` (a matplotlib Axes), draws on it, labels the axes with
units, and returns what it drew, so the CLI and the report compose them freely. Importing this
package does not import matplotlib; the modules do, and the caller chooses the backend (the CLI
uses Agg).
"""
