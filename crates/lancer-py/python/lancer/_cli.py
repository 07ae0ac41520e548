"""The `lancer` command of the wheel: the command line itself (the Rust program that the
`lancer` binary is), run in this process with this process's arguments, standard streams and
exit status."""

import signal
import sys


def main():
    """Runs `lancer` with sys.argv and exits with its status, as the binary does."""
    try:
        from . import _lancer
    except ImportError as e:  # the CPU check of the package (lancer/_cpu.py), say
        print(f"error: {e}", file=sys.stderr)
        sys.exit(1)
    # As in the binary: Ctrl-C ends the program where it has no handler of its own (a render
    # installs one that writes its checkpoint first), rather than raising in Python later.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    sys.exit(_lancer.cli_main(["lancer", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
