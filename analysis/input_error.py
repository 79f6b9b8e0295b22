"""Bad input to the analysis (no runs, an unreadable or malformed results file).

The message names the file and what was expected; command-line entry points print it as
"error: ..." and exit with code 2, as gibench does for its own bad input.
"""


class InputError(Exception):
    pass
