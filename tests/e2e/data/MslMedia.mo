// An example of the MSL's Modelica.Media, unchanged (needs Modelica 3.2.2 on
// the library path): a volume of ConstantPropertyLiquidWater heated at
// 1 MW, and a state smoothed from a second medium's to the volume's between
// t = 20 and 40 (Media.Common.smoothStep through the medium's setSmoothState).
model SimpleLiquidWater
  extends Modelica.Media.Examples.SimpleLiquidWater;
end SimpleLiquidWater;

// Properties of steam as an ideal gas (IdealGases.SingleGases.H2O, NASA
// polynomials of IdealGases.Common.SingleGasesData.H2O, a record constant)
// from 200 to 1200 K at 1 bar.
model IdealGasH2O
  extends Modelica.Media.Examples.IdealGasH2O;
end IdealGasH2O;

// Two closed volumes of gas mixtures (CombustionAir, SimpleNaturalGas) fed
// with mass and enthalpy at constant rates, their pressure and temperature
// the states.
model MixtureGases
  extends Modelica.Media.Examples.MixtureGases;
end MixtureGases;
