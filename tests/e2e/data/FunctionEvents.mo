// Relations inside a function generate no events unless the function is
// annotated GenerateEvents = true (Modelica 3.2r2 on): the half wave
// integrated into x switches between solver steps. Three kinds of function keep their
// events: one annotated GenerateEvents = true (cos crossing 0), one whose
// output is a Boolean (sin crossing 0.5) and so changes only at events, and
// the caller's own relation in an argument (time > 0.25).
model FunctionEvents
  record Parts
    Real pos;
    Real neg;
  end Parts;
  function halfWave "the positive part of u, by an if-statement"
    input Real u;
    output Real y;
  algorithm
    if u > 0 then
      y := u;
    else
      y := 0;
    end if;
  end halfWave;
  function split "the positive and negative parts of u, as a record"
    input Real u;
    output Parts p;
  algorithm
    p.pos := max(u, 0);
    p.neg := if u < 0 then u else 0;
  end split;
  function halfWaveEvents "halfWave, with events"
    input Real u;
    output Real y;
  algorithm
    y := if u > 0 then u else 0;
    annotation(GenerateEvents = true);
  end halfWaveEvents;
  function above "u > 0.5"
    input Real u;
    output Boolean b;
  algorithm
    b := u > 0.5;
  end above;
  parameter Real w = 2 * 3.141592653589793 "one period a second";
  Real x(start = 0, fixed = true) "the integral of sin's positive part";
  Real xn(start = 0, fixed = true) "the integral of sin's negative part";
  Real xe(start = 0, fixed = true) "the integral of cos's positive part";
  Real xl(start = 0, fixed = true) "the integral of the half wave from t = 0.25";
  Boolean on "sin(w t) > 0.5";
  Integer n(start = 0, fixed = true) "times on became true";
  Parts parts = split(sin(w * time));
equation
  der(x) = halfWave(sin(w * time));
  der(xn) = parts.neg;
  der(xe) = halfWaveEvents(cos(w * time));
  der(xl) = halfWave(if time > 0.25 then sin(w * time) else 0);
  on = above(sin(w * time));
  when on then
    n = pre(n) + 1;
  end when;
end FunctionEvents;
