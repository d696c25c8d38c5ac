// A switch with an arc, written as the MSL's IdealSwitchWithArc writes it: a
// nested if-equation whose branches solve for different variables (the
// closed switch's v = Ron*i, the arc's v = Varc*sign(i), the quenched
// switch's i = Goff*v). In series with a source V, a resistor R and a
// capacitor C: closed until tOff, then an arc of constant voltage Varc until
// the current falls to Varc*Goff (the quench, where v stays continuous), then
// open. Every phase is an RC charge with its own time constant, so vc is
// known exactly (tests/e2e/test_circuits.cpp).
model NestedIfSwitch
  parameter Real V = 10;
  parameter Real R = 10;
  parameter Real C = 0.01;
  parameter Real Ron = 1e-3;
  parameter Real Goff = 1e-2;
  parameter Real Varc = 2;
  parameter Real tOff = 0.05;
  Real vc(start = 0, fixed = true);
  Real v;
  Real i;
  Boolean off(start = true);
  Boolean quenched(start = true, fixed = true);
equation
  C*der(vc) = i;
  V = R*i + v + vc;
  off = time >= tOff;
  quenched = off and (abs(i) <= abs(v)*Goff or pre(quenched));
  if off then
    if quenched then
      i = Goff*v;
    else
      v = Varc*sign(i);
    end if;
  else
    v = Ron*i;
  end if;
end NestedIfSwitch;
