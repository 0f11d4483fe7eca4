"""The command lines over the package: sweep (epaphe-sweep), plot (epaphe-plot), rotor (epaphe-rotor).
Each has main(argv=None) -> exit status; the launchers in drivers/ call it."""
import argparse
import sys


def run_main(prog, run, argv):
    """run(argv) -> exit status, with a user error (EpapheError) as one line `PROG: error: ...` and
    status 1, an interrupt as status 130."""
    from ..errors import EpapheError

    try:
        return run(sys.argv[1:] if argv is None else argv)
    except EpapheError as e:
        sys.stderr.write(f"{prog}: error: {e}\n")
        return 1
    except KeyboardInterrupt:
        sys.stderr.write(f"{prog}: interrupted\n")
        return 130


class Parser(argparse.ArgumentParser):
    """argparse whose usage errors are one line `PROG: error: ... (see PROG --help)`, status 1."""

    def error(self, message):
        sys.stderr.write(f"{self.prog}: error: {message} (see {self.prog} --help)\n")
        sys.exit(1)
