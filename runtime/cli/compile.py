"""``rpo build`` and ``rpo cache``: compiling the generated model ahead of use, and the compile cache."""

from __future__ import annotations

import time

import click


def _err(msg: str) -> None:
    click.echo(msg, err=True)


@click.command("build")
@click.option("--lanes", is_flag=True, help="Also the lane library (lockstep campaigns and batches).")
@click.option("--controller", "controllers", multiple=True, metavar="NAME",
              help="Only the plant and this controller (repeatable; default: every controller).")
def build_cmd(lanes: bool, controllers: tuple[str, ...]) -> int:
    """Compile the generated model now, rather than piece by piece on first use.

    rpo compiles on first use only what a command calls (a run: its step and the plant copy its
    parameters select); this compiles every function (and with --lanes their lane forms) into the
    cache, for a machine that should never wait later.  (`python build.py` is another thing: it
    regenerates generated/ from symbolic/.)
    """
    from rpo.runtime.model.loader import load_model

    model = load_model("compiled", log=_err, controllers=list(controllers) or None)
    t0 = time.perf_counter()
    model.prepare(list(model.functions))
    _err(f"scalar library: {model.library}")
    if lanes:
        lib = model.lanes()
        assert lib is not None
        _err(f"lane library ({lib.width} lanes): {lib.path}")
    _err(f"built in {time.perf_counter() - t0:.1f} s")
    return 0


@click.command()
@click.option("--prune", is_flag=True, help="Delete the objects and libraries the current generated/ does not use.")
@click.option("--dry-run", is_flag=True, help="With --prune: only say what would be deleted.")
def cache(prune: bool, dry_run: bool) -> int:
    """The compile cache ($RPO_CACHE_DIR, else ~/.cache/rpo): where it is and how large; --prune."""
    from rpo.runtime.model.cache import cache_dir
    from rpo.runtime.model.library import prune_cache

    root = cache_dir()
    files = [f for f in root.rglob("*") if f.is_file() and not f.name.startswith(".")] if root.is_dir() else []
    total = sum(f.stat().st_size for f in files)
    libs = sum(1 for f in files if f.suffix == ".so")
    click.echo(f"cache            {root}: {len(files) - libs} objects, {libs} libraries, {total / 1e6:.1f} MB")
    if prune:
        n, size = prune_cache(dry_run=dry_run)
        verb = "would delete" if dry_run else "deleted"
        click.echo(f"pruned           {verb} {n} files ({size / 1e6:.1f} MB) the current generated/ does not use")
    return 0
