"""One module per subcommand of ``python -m taichi_bearing``."""
