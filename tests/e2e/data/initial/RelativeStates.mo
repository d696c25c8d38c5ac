// A mass on a damper to a fixed housing, with the damper's relative position
// and velocity preferred as states (as the MSL's compliant elements): the
// mass's own s(fixed = true) and v(fixed = true) must become those states'
// initial values. m der(v) = -d v: v = 10 exp(-25 t), s = 3 + 0.4 (1 - exp(-25 t)).
model RelativeStates
  parameter Real s0 = 4.5 "housing position";
  parameter Real L = 1 "mass length";
  parameter Real d = 25 "damping";
  parameter Real m = 1 "mass";
  Real s(start = 3, fixed = true) "mass centre";
  Real v(start = 10, fixed = true) "mass velocity";
  Real s_rel(start = 0, stateSelect = StateSelect.prefer) "housing - mass flange";
  Real v_rel(start = 0, stateSelect = StateSelect.prefer);
  Real f "damper force";
equation
  v = der(s);
  m*der(v) = f;
  s_rel = s0 - (s + L/2);
  v_rel = der(s_rel);
  f = d*v_rel;
end RelativeStates;
