"""Implementations of the command-line subcommands (one module each)."""
