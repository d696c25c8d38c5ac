// fixed = true on variables that are not states: the relative position and
// velocity of a damper are preferred as states (as in the MSL's
// PartialCompliantWithRelativeStates), the mass's own s and v are declared
// fixed. The states must start where the fixed values put them:
// s_rel(0) = 4.5 - 3 = 1.5, v_rel(0) = -10; then v = 10 exp(-25 t).
model FixedNonState
  parameter Real d = 25;
  Real s(start = 3, fixed = true);
  Real v(start = 10, fixed = true);
  Real s_rel(start = 0, stateSelect = StateSelect.prefer);
  Real v_rel(start = 0, stateSelect = StateSelect.prefer);
equation
  s_rel = 4.5 - s;
  v_rel = der(s_rel);
  v = der(s);
  der(v) = d*v_rel;
end FixedNonState;
