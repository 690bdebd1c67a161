"""The runner's one-line errors. Each is printed as ``wirenet run: error: MESSAGE`` with exit
code 2; the message names what the user wrote (the file, the key, the value)."""


class CaseFileError(Exception):
    """A case file that cannot run as written: FILE: KEY: what is wrong."""


class StudyError(Exception):
    """A bad command, study file or output folder."""


class RunError(Exception):
    """A case that failed while it ran: its folder and what went wrong (LIGGGHTS' ERROR line)."""
