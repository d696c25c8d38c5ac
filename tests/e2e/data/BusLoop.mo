// Expandable connectors (MLS 9.1.3): a plant puts its speed on a sub-bus of
// its own; the controller reads it from the main bus and puts its command on
// the bus as an element that no bus declares. `spare` and `enabled` are
// declared but connected nowhere, so they are no variables.
// Closed form: T w' = k (1 - w) - w, w(0) = 0, so
// w(t) = k / (k + 1) (1 - exp(-(k + 1) t / T)).
package BusLoop
  connector RealOutput = output Real;
  connector RealInput = input Real;
  expandable connector SubBus
    Real speed;
    Real spare;
  end SubBus;
  expandable connector Bus
    SubBus sub;
    Boolean enabled;
  end Bus;
  model Plant
    parameter Real T = 2;
    SubBus sub;
    RealInput u;
    RealOutput w(start = 0, fixed = true);
  equation
    T * der(w) = u - w;
    connect(w, sub.speed);
  end Plant;
  model Controller
    parameter Real k = 3;
    Bus bus;
    RealOutput u;
    Real e;
  equation
    e = 1 - bus.sub.speed;
    u = k * e;
    connect(u, bus.command);
  end Controller;
  model Loop
    Plant plant;
    Controller ctrl;
    Bus bus;
  equation
    connect(plant.sub, bus.sub);
    connect(ctrl.bus, bus);
    connect(bus.command, plant.u);
  end Loop;
end BusLoop;
