// terminate() in a when-clause (MLS 8.3.8): the run ends successfully at the
// event, with the message; the MSL's Blocks.Logical.TerminateSimulation
// writes it so (RobotR3 uses it). A ball thrown up: the run stops when it
// falls back below its start, after the clause's other assignment.
model TerminateWhen
  parameter Real v0 = 4;
  parameter String text = "fell back below the start";
  Real h(start = 0, fixed = true);
  Real v(start = v0, fixed = true);
  Integer landings(start = 0, fixed = true);
equation
  der(h) = v;
  der(v) = -9.81;
  when h < 0 then
    landings = pre(landings) + 1;
    terminate(text);
  end when;
end TerminateWhen;
