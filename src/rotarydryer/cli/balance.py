"""``rotarydryer balance``: overall energy balance of a plant test (gas flow implied by the data)."""

from typing import Optional

import typer

from .._io import json_text
from . import app


@app.command("balance", short_help="Gas flow that closes a plant test's energy balance.")
def balance(
    ajayi_test: Optional[int] = typer.Option(None, "--ajayi-test",
                                             help="Take the measured values of Ajayi's PI test 1-6 (MMG Karumba); "
                                                  "options given explicitly override them."),
    gas_in: Optional[float] = typer.Option(None, help="Gas inlet temperature, degC."),
    gas_out: Optional[float] = typer.Option(None, help="Gas outlet temperature, degC (measured)."),
    feed: Optional[float] = typer.Option(None, help="Wet feed rate, kg/s."),
    moisture_in: Optional[float] = typer.Option(None, help="Feed moisture, kg/kg wet basis."),
    moisture_out: Optional[float] = typer.Option(None, help="Product moisture, kg/kg wet basis."),
    product_temperature: Optional[float] = typer.Option(None, help="Product temperature, degC."),
    feed_temperature: float = typer.Option(28.0, help="Feed temperature, degC (Ajayi l.3241)."),
    gas_humidity: float = typer.Option(0.0193 / (1 - 0.0193), help="Inlet gas humidity, kg/kg dry gas (Ajayi l.3227)."),
    shell_loss: float = typer.Option(0.0, help="Shell heat loss, W (the physical MMG model: ~0.4e6)."),
    gas_flow: Optional[float] = typer.Option(None, help="If given: solve the gas OUTLET temperature that this gas "
                                                        "flow (kg/s wet) allows, instead of the gas flow."),
    material: str = typer.Option("zinc_concentrate_ajayi2011", help="Library material of the solids, for their heat "
                                 "capacities (the case's [material] name); default Ajayi's MMG zinc concentrate."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
):
    """Gas flow (kg/s) that closes a test's energy balance on its measured inlets and outlets, the
    exhaust humidity and dew point; or, with --gas-flow, the gas outlet temperature it allows.

    Any energy-conserving dryer model obeys this balance (rotarydryer.thermal.consistency).

    \b
    Examples:
      rotarydryer balance --ajayi-test 6 --shell-loss 0.38e6
      rotarydryer balance --ajayi-test 6 --gas-flow 16.25 --shell-loss 0.38e6
      rotarydryer balance --material raw_sugar_lee2008 --gas-in 150 --gas-out 60 --feed 27 --moisture-in 0.008 --moisture-out 0.004 --product-temperature 45
    """
    import math

    from .._limits import check_key
    from .._validation import check_range
    from ..properties import humid_air as ha
    from ..properties.materials import list_materials, load_material
    from ..thermal.consistency import balance_gas_outlet_temperature, implied_gas_flow, pi_test_conditions
    from ..thermal.streams import evaporation_rate, exhaust_humidity

    try:
        if ajayi_test is not None and ajayi_test not in range(1, 7):
            raise ValueError(f"--ajayi-test = {ajayi_test} is not one of Ajayi's tests 1-6")
        base = pi_test_conditions(ajayi_test) if ajayi_test is not None else {}
        vals = {"gas_in": gas_in if gas_in is not None else base.get("gas_in_c"),
                "gas_out": gas_out if gas_out is not None else base.get("gas_out_c"),
                "feed": feed if feed is not None else base.get("feed_rate"),
                "moisture_in": moisture_in if moisture_in is not None else base.get("moisture_in"),
                "moisture_out": moisture_out if moisture_out is not None else base.get("moisture_out"),
                "product_temperature": (product_temperature if product_temperature is not None
                                        else base.get("product_c"))}
        need = [k for k, v in vals.items() if v is None and not (k == "gas_out" and gas_flow is not None)]
        if need:
            raise ValueError("missing " + ", ".join("--" + k.replace("_", "-") for k in need)
                             + " (or give --ajayi-test N)")
        # every value checked under the option the user set (plain numbers, ranges, units)
        for opt, v, lo, hi, lo_in, unit in (
                ("--gas-in", vals["gas_in"], 0.0, 600.0, True, "degC"),
                ("--gas-out", vals["gas_out"], 0.0, 600.0, True, "degC"),
                ("--feed", vals["feed"], 0.0, math.inf, False, "kg/s"),
                ("--moisture-in", vals["moisture_in"], 0.0, 1.0, True, "kg/kg wet"),
                ("--moisture-out", vals["moisture_out"], 0.0, 1.0, True, "kg/kg wet"),
                # up to the gas's own bound (and below --gas-in, checked next): a product at 415 degC that simulate
                # gave was refused above 300 (found by fuzzing)
                ("--product-temperature", vals["product_temperature"], -20.0, 600.0, False, "degC"),
                ("--gas-humidity", gas_humidity, 0.0, 0.3, True, "kg/kg dry gas"),
                ("--shell-loss", shell_loss, 0.0, math.inf, True, "W"),
                ("--gas-flow", gas_flow, 0.0, 1000.0, False, "kg/s")):      # gas.flow's upper bound, one range
            if v is not None:
                check_range(opt, v, lo, hi, low_inclusive=lo_in, high_inclusive=opt == "--gas-flow", unit=unit)
        # the case key's range: a wet feed at or above 99 degC would boil, which no balance of a dryer holds
        check_key("operating.feed_temperature", feed_temperature, "--feed-temperature")
        if gas_flow is not None:
            check_key("gas.flow", gas_flow, "--gas-flow")      # the case key's range
            if gas_out is not None:      # the measured outlet was ignored for the solved one (found by fuzzing)
                raise ValueError(f"--gas-out = {gas_out:g} degC and --gas-flow = {gas_flow:g} kg/s: give one; the "
                                 "balance solves the other (--gas-flow: the outlet temperature, --gas-out: the flow)")
        if vals["product_temperature"] > vals["gas_in"]:
            raise ValueError(f"--product-temperature = {vals['product_temperature']:g} degC is above --gas-in = "
                             f"{vals['gas_in']:g} degC: the solids do not leave hotter than the gas that heats them")
        if vals["moisture_out"] >= vals["moisture_in"]:
            raise ValueError(f"--moisture-out = {vals['moisture_out']:g} must be below --moisture-in = "
                             f"{vals['moisture_in']:g} kg/kg wet: the balance needs a test that dries")
        if vals["gas_out"] is not None and gas_flow is None and vals["gas_out"] >= vals["gas_in"]:
            raise ValueError(f"--gas-out = {vals['gas_out']:g} degC must be below --gas-in = {vals['gas_in']:g} degC")
        if material not in list_materials():
            raise ValueError(f"--material {material!r} is not in the materials library ({', '.join(list_materials())})")
        mat = load_material(material)
        kw = dict(gas_in_c=vals["gas_in"], gas_humidity_in=gas_humidity, feed_rate=vals["feed"],
                  moisture_in=vals["moisture_in"], moisture_out=vals["moisture_out"], solids_in_c=feed_temperature,
                  solids_out_c=vals["product_temperature"], heat_loss=shell_loss,
                  solids_heat_capacity=mat.heat_capacity, water_heat_capacity=mat.water_heat_capacity)
        evap = float(evaporation_rate(vals["feed"], vals["moisture_in"], vals["moisture_out"]))
        try:
            if gas_flow is None:
                g = implied_gas_flow(gas_out_c=vals["gas_out"], **kw)
                out = {"gas_flow_kg_s": g, "gas_outlet_temperature_degC": vals["gas_out"]}
            else:
                g = gas_flow
                out = {"gas_flow_kg_s": g,
                       "gas_outlet_temperature_degC": balance_gas_outlet_temperature(gas_flow, **kw)}
        except ValueError as exc:   # its reason names the balance's own terms (humidity, heat_loss): say whose inputs
            raise ValueError(f"these inputs have no energy balance ({exc}); check --feed, --moisture-in and "
                             f"--moisture-out (evaporation {evap:.4g} kg/s), "
                             f"{'--gas-out' if gas_flow is None else '--gas-flow'}, --gas-in, --feed-temperature, "
                             "--product-temperature and --shell-loss") from None
    except ValueError as exc:
        typer.echo(f"error: {exc}", err=True)
        raise typer.Exit(2)
    y_out = exhaust_humidity(g, gas_humidity, evap)
    dew = float(ha.dew_point(min(y_out, 0.3)))
    out.update({"material": material, "evaporation_kg_s": evap, "exhaust_humidity_kg_kg": y_out, "exhaust_dew_point_degC": dew,
                "product_temperature_degC": vals["product_temperature"], "shell_heat_loss_W": shell_loss,
                "product_below_dew_point": bool(vals["product_temperature"] < dew),
                "exhaust_below_dew_point": bool(out["gas_outlet_temperature_degC"] < dew)})
    from .._display import show, show_delta

    t_out = out["gas_outlet_temperature_degC"]
    said = []       # in the display units (--units; the options and the JSON are SI)
    if t_out < dew:
        said.append(f"warning: the exhaust ({show(t_out, 'temperature')}) is {show_delta(dew - t_out, 'temperature')} "
                    f"below its own dew point ({show(dew, 'temperature')}): the gas "
                    f"would be supersaturated, which the balance does not represent (water would condense); its "
                    f"numbers hold, the gas state does not: a hotter --gas-in, more gas or a wetter --moisture-out")
    if out["product_below_dew_point"]:
        said.append(f"warning: the product ({show(vals['product_temperature'], 'temperature')}) is colder than the "
                    f"exhaust dew point: it would condense water, not dry (measured after discharge? air leaking in?)")
    if as_json:     # the JSON alone on stdout; its warnings on stderr, as the other commands give them
        typer.echo(json_text(out, indent=2))
        for line in said:
            typer.echo(line, err=True)
        return
    solved = "gas flow" if gas_flow is None else "gas outlet temperature"
    typer.echo(f"solved for: {solved}")
    typer.echo(f"gas flow                 {show(out['gas_flow_kg_s'], 'mass_flow')} (wet)")
    typer.echo(f"gas outlet temperature   {show(t_out, 'temperature')}")
    typer.echo(f"evaporation              {show(evap, 'mass_flow')}")
    typer.echo(f"exhaust humidity         {show(y_out, 'humidity')} dry gas (dew point {show(dew, 'temperature')})")
    for line in said:
        typer.echo(line)
