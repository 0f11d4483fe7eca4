"""The errors of the package: what a user did wrong, said in one line (file, key, value, the fix)."""


class EpapheError(Exception):
    """A user error: a missing or foreign file, an unknown key, body or node set, a bad value.
    Command lines print it as one line `PROG: error: <message>` and exit with status 1."""


class UnknownName(EpapheError, KeyError):
    """An unknown body, node set, key...: the message names the valid choices."""

    def __str__(self):  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
