// A base inherited along two paths with different modifiers: two different
// sets of elements, which Modelica does not merge (MLS 7.3).
model InheritedAgainOtherModifiers
  partial model Base
    parameter Real k = 1;
    Real x = k;
  end Base;
  partial model Left
    extends Base(k = 2);
  end Left;
  model Both
    extends Left;
    extends Base(k = 3);
  end Both;
  Both both;
end InheritedAgainOtherModifiers;
