// Records through functions, equations and bindings (MLS 12.6), each result
// known in closed form (tests/e2e/test_records.cpp, tests/frontend/test_records.cpp).
package Records
  record Spring
    Real k "stiffness";
    Real c = 0 "damping";
  end Spring;

  record State
    Real x;
    Real v;
  end State;

  function accel "a record in, a record out, a default argument"
    input State s;
    input Spring sp;
    input Real m = 1;
    output State ds;
  algorithm
    ds.x := s.v;
    ds.v := -(sp.k * s.x + sp.c * s.v) / m;
  end accel;

  model Oscillator "x = cos(sqrt(k/m) t) for c = 0"
    parameter Spring sp = Spring(k = 4);
    parameter Real m = 1;
    State s(x(start = 1, fixed = true), v(start = 0, fixed = true));
    State ds;
  equation
    ds = accel(s, sp, m);
    der(s.x) = ds.x;
    der(s.v) = ds.v;
  end Oscillator;

  record Pt
    Real x;
    Real y;
  end Pt;

  record Seg "a nested record with an array field and a default"
    Pt a;
    Pt b;
    Real w[2] = {1, 1};
  end Seg;

  function len
    input Seg s;
    output Real l;
  algorithm
    l := sqrt((s.b.x - s.a.x)^2 + (s.b.y - s.a.y)^2) * (s.w[1] + s.w[2]) / 2;
  end len;

  function flip "a protected record, assigned whole"
    input Pt p;
    input Real k = 1;
    output Pt q;
  protected
    Pt tmp;
  algorithm
    tmp := p;
    q.x := k * tmp.y;
    q.y := k * tmp.x;
  end flip;

  function rightmost "an array of records, a loop, a record chosen by a varying condition"
    input Pt ps[:];
    output Pt best;
  algorithm
    best := ps[1];
    for i in 2:size(ps, 1) loop
      if ps[i].x > best.x then
        best := ps[i];
      end if;
    end for;
  end rightmost;

  model Geometry
    parameter Pt c = Pt(3, 4);
    parameter Seg sg(a(x = 0, y = 0), b(x = 3, y = 4), w = {2, 4});
    parameter Pt corners[2] = {Pt(1, 2), Pt(y = 4, x = 3)};
    Pt w "(3 t, 6)";
    Pt v "the rightmost of c, w and (2 + t, 1)";
    Real n "|w - c|";
    Real L "15";
    Real area;
    output Real y[7] = {w.x, w.y, v.x, v.y, n, L, area};
  equation
    w = flip(Pt(y = time, x = 2), k = 3);
    v = rightmost({c, w, Pt(2 + time, 1)});
    n = len(Seg(a = c, b = w));
    L = len(sg);
    area = (corners[2].x - corners[1].x) * (corners[2].y - corners[1].y);
  end Geometry;
end Records;
