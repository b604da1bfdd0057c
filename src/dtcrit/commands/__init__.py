"""One module per ``dtcrit`` subcommand: ``add_parser(subparsers)`` and ``run(args) -> int``."""
