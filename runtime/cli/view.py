"""``rpo view RUN_FOLDER [--out FILE]``: the interactive page of a results folder
(:mod:`rpo.runtime.outputs.page`), registered on the ``rpo`` group by :mod:`rpo.runtime.cli.main`."""

from __future__ import annotations

from pathlib import Path

import click


@click.command()
@click.argument("folder", type=click.Path(path_type=Path))
@click.option("--out", "out", type=click.Path(path_type=Path), default=None,
              help="The page to write (default: RUN_FOLDER/view.html); an existing file is replaced only if "
                   "rpo view wrote it.")
def view(folder: Path, out: Path | None) -> int:
    """Write an interactive page of the run RUN_FOLDER (written by `rpo run`): one offline HTML file
    with the 3D approach (both bodies' axes, the camera cone and the keep-out sphere, animated) and
    the errors the verdict judges, the distance and the camera margin, linked by a time slider."""
    from rpo.runtime.outputs.page import write_page

    click.echo(f"wrote {write_page(folder, out)}")
    return 0
