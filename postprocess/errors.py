"""The one exception type the command line turns into a one-line error and exit code 2."""


class PostprocessError(Exception):
    """A user-facing error; the message is printed as is after ``postprocess CMD: error:``."""


def at(path, line, message):
    """Return a PostprocessError whose message names the file and the line."""
    return PostprocessError(f"{path}:{line}: {message}")
