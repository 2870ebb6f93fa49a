"""Running ``impedax`` in-process for the command-line tests: exit code, stdout and stderr."""

from impedax.cli import main


def run(argv, capsys):
    """``impedax *argv`` through `impedax.cli.main` (argparse's own errors included, as their
    SystemExit code): (exit code, stdout, stderr)."""
    try:
        code = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse's own errors
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err
