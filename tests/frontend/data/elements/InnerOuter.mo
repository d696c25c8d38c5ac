// `outer` elements refer to the nearest enclosing instance's `inner` one of
// the same name: both rooms see the environment of the house they are in;
// the inner environment of `house2` hides the top-level one.
model InnerOuter
  model Environment
    parameter Real T = 290;
    Real Tnow = T + time;
  end Environment;
  model Room
    outer Environment env;
    Real T(start = 280, fixed = true);
  equation
    der(T) = env.Tnow - T;
  end Room;
  model House
    Room r1;
    Room r2;
  end House;
  model OwnHouse
    inner Environment env(T = 300);
    Room r;
  end OwnHouse;
  House house1;
  OwnHouse house2;
  inner Environment env;
end InnerOuter;
