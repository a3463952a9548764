"""One module per CLI subcommand (see ``spiralcap.cli.COMMANDS``)."""
