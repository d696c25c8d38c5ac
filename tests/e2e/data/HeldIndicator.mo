// A relation whose indicator is exactly 0 when the integration restarts and
// then leaves 0 without changing sign, as the MSL's clutch normal force
// fn = 0 before a ramp starts (`free = fn <= 0`): the mode must switch when
// v leaves 0 (tests/e2e/test_friction_modes.cpp). Exact: x = max(0, t - 1).
model HeldIndicator
  Real v(start = 0, fixed = true) "exactly 0 until t = 1, then t - 1";
  Real x(start = 0, fixed = true);
  Boolean on(start = false);
  Integer mode(start = 2);
equation
  when time >= 1 then
    on = true;
  end when;
  der(v) = if on then 1 else 0;
  mode = if v <= 0 then 2 else if pre(mode) == 2 then -1 else pre(mode);
  der(x) = if mode == 2 then 0 else 1;
end HeldIndicator;
