// An enumeration type as an array dimension, indexed by its literals and
// iterated by a for-loop over the type. Solution: u[k] = exp(-rate[k] t).
model EnumerationIndexed
  type Axis = enumeration(x, y, z);
  parameter Real rate[Axis] = {1, 2, 4};
  Real u[Axis](each start = 1, each fixed = true);
  Real fastest;
equation
  for k in Axis loop
    der(u[k]) = -rate[k] * u[k];
  end for;
  fastest = u[Axis.z] - u[Axis.x];
end EnumerationIndexed;
