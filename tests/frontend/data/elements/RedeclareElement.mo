// A `redeclare` component element of a class replaces the inherited
// replaceable one: new type, new binding.
model RedeclareElement
  connector Pin
    Real v;
    flow Real i;
  end Pin;
  model Base
    replaceable parameter Real gain = 1;
    replaceable Pin p;
    Real u = gain * time;
  equation
    p.v = u;
  end Base;
  model Twice
    extends Base;
    redeclare parameter Real gain = 2;
  end Twice;
  Twice t;
end RedeclareElement;
