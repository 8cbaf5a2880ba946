"""Heat and mass transfer building blocks of the dryer (issue 6).

Modules
-------
burner
    Combustion chamber of Ajayi (2011) Appendix A: fuel oil + combustion and dilution
    air -> hot-gas flow, composition and temperature; inverse (fuel for a set temperature).
shell
    Shell heat-loss network with the shell temperature solved (inside convection and
    gas radiation, scale / steel / insulation conduction, outside natural convection and
    radiation); Ajayi's loss factor as a compatibility option.
drying
    Drying-rate kinetics (Ajayi's Chilton-Colburn mass-transfer form, constant + falling
    rate, characteristic drying curve) and Song's (2003) pilot Ua estimates.
streams
    Enthalpy of gas and solids streams (physical, Ajayi's, Ajayi's as coded) and the
    overall energy balance on outlet data (implied shell loss).
consistency
    Is a plant test energetically consistent? Gas flow implied by measured inlets and
    outlets, the gas outlet temperature a given gas flow allows, and the bound any
    energy-conserving model obeys (applied to Ajayi's PI tests).
radiation
    H2O/CO2 gas emissivity (weighted sum of grey gases, Smith et al. 1982), mean beam
    length, gas-wall and gas-solids radiative exchange.

The dryer-level model: ``dryer`` (equations and solvers), ``settings``, ``states``; studies: ``studies``.
"""
