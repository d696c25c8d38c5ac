// The author's initial condition decides the state: T has a fixed start;
// y, which the model differentiates (dy = der(y)) and which has a start
// value too, follows T only from t = 20 on (its weight on T is 0 before,
// as Modelica.Media's smoothed states). With y as the state, T would be
// (y - (1 - w) 280) / w: undefined until t = 20.
model FixedStartState
  Real T(start = 300, fixed = true);
  Real U "T (10 + T / 1000), whose rate the model gives";
  Real y(start = 280);
  Real dy;
  Real w = smooth(1, if time < 20 then 0 else if time > 40 then 1 else (time - 20)^2 * (3 * 20 - 2 * (time - 20)) / 20^3);
equation
  U = T * (10 + 0.001 * T);
  der(U) = 1;
  y = w * T + (1 - w) * 280;
  dy = der(y);
end FixedStartState;
