// Two steps that hand over to each other after `wait` (the MSL's
// StateGraph.Examples.FirstExample, reduced): both timers' indicators
// time - ta - wait and time - tb - wait cross zero at t = wait, and step B's
// clause restarts its timer (tb := time) in the event iteration. Its
// relation must then read time >= tb + wait as false again: held at its
// crossing's value it made B leave at once, A enter, and so on without end.
// A is active on [0, 1), [2, 3), ...; B on [1, 2), [3, 4), ...
model TwoStepTimers
  parameter Real wait = 1;
  Boolean a(start = true, fixed = true) "step A active";
  Boolean b(start = false, fixed = true) "step B active";
  discrete Real ta(start = 0, fixed = true) "when A was entered";
  discrete Real tb(start = 0, fixed = true) "when B was entered";
  Boolean leaveA;
  Boolean leaveB;
  Integer entries(start = 0, fixed = true) "steps entered after the start";
equation
  leaveA = pre(a) and time >= ta + wait;
  leaveB = pre(b) and time >= tb + wait;
  a = pre(a) and not leaveA or leaveB;
  b = pre(b) and not leaveB or leaveA;
  when a then
    ta = time;
  end when;
  when b then
    tb = time;
  end when;
  when {a, b} then
    entries = pre(entries) + 1;
  end when;
end TwoStepTimers;
