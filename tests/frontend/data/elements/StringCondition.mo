// A conditional component switched by a comparison of a String parameter,
// as the MSL's machines write `Star star if terminalConnection <> "D"`.
model StringCondition
  model Machine
    parameter String terminalConnection = "Y";
    Real star = 1 if terminalConnection <> "D";
    Real delta = 2 if terminalConnection == "D";
  end Machine;
  Machine y;
  Machine d(terminalConnection = "D");
end StringCondition;
