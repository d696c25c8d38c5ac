// An example of the MSL's Modelica.Media, unchanged (needs Modelica 3.2.2 on
// the library path): a volume of ConstantPropertyLiquidWater heated at
// 1 MW, and a state smoothed from a second medium's to the volume's between
// t = 20 and 40 (Media.Common.smoothStep through the medium's setSmoothState).
model SimpleLiquidWater
  extends Modelica.Media.Examples.SimpleLiquidWater;
end SimpleLiquidWater;
