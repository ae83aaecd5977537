"""Each command of the command line is a module-level click command: imported from its
family's module and invoked alone, it runs as it does in the ``stickslip`` group."""

from __future__ import annotations

import json

import click
import pytest
from click.testing import CliRunner

from stickslip.cli.options import LawCommand, OnceCommand, law_command


def test_cycle_imported_from_its_module_runs_alone() -> None:
    """``cycle --nu 0.01 --c 3.8`` (F1 at a slow drive) sticks and slips. Independently of
    the engine: in a steady cycle the block advances as far as the drive, nu * period; and
    while it sticks the spring force (in units of the static friction force) rises at rate
    nu from its lowest value to the static threshold 1."""
    from stickslip.cli.dynamics import cycle

    assert isinstance(cycle, LawCommand)
    res = CliRunner().invoke(cycle, ["--nu", "0.01", "--c", "3.8", "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    assert d["regime"] == "stick-slip"
    assert {k: d["parameters"][k] for k in ("nu", "law", "c")} == {"nu": 0.01, "law": "weakening", "c": 3.8}
    assert d["slip_distance"] == pytest.approx(0.01 * d["period"], rel=1e-9)
    assert d["min_force"] + 0.01 * d["stick_time"] == pytest.approx(1.0, abs=1e-3)
    assert d["stick_fraction"] == pytest.approx(d["stick_time"] / d["period"], rel=1e-9)


def test_a_command_alone_refuses_what_the_group_refuses() -> None:
    from stickslip.cli.dynamics import cycle

    res = CliRunner().invoke(cycle, ["--nu", "0.01", "--c", "3", "--c", "4"])
    assert res.exit_code == 2
    assert "option --c is given more than once" in res.output


def test_the_group_holds_the_module_level_commands_in_the_help_order() -> None:
    from stickslip.cli import bifurcation, chain, data, dynamics, explore, paper, ratestate
    from stickslip.cli.commands import main

    assert main.commands["cycle"] is dynamics.cycle
    assert main.commands["sweep"] is dynamics.sweep
    assert main.commands["regimes"] is bifurcation.regimes
    assert main.commands["chain"] is chain.chain
    assert main.commands["fit"] is data.fit
    assert main.commands["explore"] is explore.explore
    assert main.commands["reproduce"] is paper.reproduce
    assert main.commands["ratestate-fit"] is ratestate.ratestate_fit
    assert main.commands["earthquake-cycles"] is ratestate.earthquake_cycles
    assert list(main.commands)[:4] == ["cycle", "simulate", "sweep", "reproduce"]
    assert all(isinstance(c, OnceCommand) for c in main.commands.values())


def test_law_command_builds_a_command_with_or_without_a_group() -> None:
    @law_command(default_law="coulomb")
    def alone(**opts: object) -> None:
        click.echo(opts["law"])

    group = click.Group("g")

    @law_command(group, "attached")
    def attached(**opts: object) -> None:
        click.echo(opts["law"])

    assert isinstance(alone, LawCommand) and alone.name == "alone"
    assert group.commands == {"attached": attached}
    assert CliRunner().invoke(alone, []).output == "coulomb\n"
    assert CliRunner().invoke(group, ["attached"]).output == "weakening\n"
