"""The shipped scenario files, installed as the package ``rpo.scenarios`` (data only, no code).

This folder stays at the top of the repository, where the scenarios are edited and where the docs
cite them (``scenarios/000_scenario_III.toml``); this file makes it the package ``rpo.scenarios``
(setup.py maps it), so an installed rpo reads its scenarios with :mod:`importlib.resources` in
every install mode: ``rpo scenarios`` lists them and copies one out, ``paper_data()`` reads them
(:mod:`rpo.runtime.scenario.shipped`).
"""
