"""What every FE study's figure ends with (matplotlib, Agg): the axes labelled along x, gridded and given their
legends, the figure laid out, written and closed."""


def finish(fig, axes, xlabel, path):
    """Label every axis of ``axes`` along x with ``xlabel``, grid it, show its legend; save ``fig`` to ``path``."""
    import matplotlib.pyplot as plt
    for a in axes:
        a.set_xlabel(xlabel)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
