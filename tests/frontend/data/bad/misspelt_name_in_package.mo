// expect: unknown component 'levle', once: searching the enclosing package
// for the name must not also report that package's extends (whose base is a
// class of its own nested package).
package Plant
  extends Decoration.Base;
  package Decoration
    partial package Base
    end Base;
  end Decoration;
  model Tank
    parameter Real area = 2;
    Real level(start = 1, fixed = true);
  equation
    area * der(level) = -levle;
  end Tank;
end Plant;

model UseTank
  Plant.Tank tank;
end UseTank;
