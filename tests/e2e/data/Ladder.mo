// A capacitor discharging into a ladder of N series resistors R with shunt
// resistors Rs to ground: the node voltages are one linear block of N
// unknowns (solved by sparse LU for N >= 32), the capacitor sees
// Req = R + Z_1 with Z_N = Rs, Z_i = Rs || (R + Z_{i+1}).
model Ladder
  parameter Integer N = 40;
  parameter Real R = 1, Rs = 3, C = 0.5;
  Real u(start = 1, fixed = true) "capacitor voltage";
  Real v[N] "node voltages";
equation
  C * der(u) = -(u - v[1]) / R;
  (u - v[1]) / R = v[1] / Rs + (v[1] - v[2]) / R;
  for i in 2:N-1 loop
    (v[i-1] - v[i]) / R = v[i] / Rs + (v[i] - v[i+1]) / R;
  end for;
  (v[N-1] - v[N]) / R = v[N] / Rs;
end Ladder;
