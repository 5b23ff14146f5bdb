"""What each exit code of ``mpcwalk`` means: one thing each."""

#: Exit code -> its meaning.
EXIT_CODES = {
    0: "walked (or the command succeeded)",
    1: "the robot fell (or a check of `robots check` failed, its loading included)",
    2: "bad input, refused before anything ran (`robots check`: no such robot or preset file)",
    3: "the controller stopped the walk: faults beyond its bound",
    4: "internal error (traceback saved under --out; --debug prints it)",
    130: "interrupted (SIGINT): the partial walk's results are written",
}

#: A walk's outcome -> the exit code of ``mpcwalk walk``.
OUTCOME_EXIT = {"walked": 0, "fell": 1, "stopped": 3, "interrupted": 130}

__all__ = ["EXIT_CODES", "OUTCOME_EXIT"]
