// Examples of the MSL's Rotational library, unchanged (needs Modelica 3.2.2
// on the library path), whose friction elements get stuck together: the
// linear block of the stuck configuration is singular, its equations
// consistent (tests/e2e/test_singular_blocks.cpp).

// A LossyGear between two inertias and a BearingFriction on the first: when
// both are stuck, how they share the torque is undetermined ("Still a
// reliable Modelica simulator should be able to handle this situation").
model LossyGearDemo2
  extends Modelica.Mechanics.Rotational.Examples.LossyGearDemo2;
end LossyGearDemo2;
