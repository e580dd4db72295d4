"""pytest configuration for running the book's notebooks with nbval.

nbval 0.10+ executes cells with ``store_history=False``, which makes IPython
ignore a trailing ``;`` (nbval issue #194, IPython issue #14162): a cell such as
``ax.set_title("...");`` then yields an extra ``Text(...)`` output and the
comparison with the stored notebook fails. Executing with history on, as
Jupyter itself does, restores the usual behaviour.
"""

from nbval.kernel import RunningKernel


def _execute_cell_input(self, cell_input, allow_stdin=None):
    return self.kc.execute(
        cell_input, store_history=True, allow_stdin=allow_stdin, stop_on_error=False
    )


RunningKernel.execute_cell_input = _execute_cell_input
