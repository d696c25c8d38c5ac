// Elements used before their declaration is reached (MLS 5.3: declaration
// order does not matter). A base class's redeclaration reads a parameter the
// derived class declares after its extends clause (the MSL machines'
// `redeclare ThermalPortSMPM internalThermalPort(final useDamperCage =
// useDamperCage)`), which switches a conditional component off; and two
// siblings' modifiers each read the other's member to size an array
// (the MSL's RadioButtonSource `start(reset = {stop.on})`).
model ForwardReferences
  model Port
    parameter Boolean withExtra(start = true);
    Real e = 1;
    Real extra = 2 if withExtra;
  end Port;
  partial model Base
    replaceable Port port;
  end Base;
  model Machine
    extends Base(redeclare Port port(final withExtra = withExtra));
    parameter Boolean withExtra(start = true);
  end Machine;
  block Button
    input Boolean reset[:] = {false};
    output Boolean on;
    parameter Integer n = size(reset, 1);
  equation
    on = not reset[n];
  end Button;
  Machine m(withExtra = false);
  Button a(reset = {b.on});
  Button b(reset = {time > 1, a.on});
end ForwardReferences;
