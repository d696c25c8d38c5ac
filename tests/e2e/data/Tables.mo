// Tables as the MSL's ModelicaStandardTables library declares them: an
// external object whose constructor and functions are external "C"
// functions that mocompile provides itself (frontend/src/flatten_tables.cpp).
// Written here from scratch (the MSL's CombiTimeTable and CombiTable1D have
// the same shape), so that the tests need no MSL.
package Tables
  class TimeTable "a table whose first column is time"
    extends ExternalObject;
    function constructor
      input String tableName;
      input String fileName;
      input Real table[:, :];
      input Real startTime;
      input Integer columns[:];
      input Integer smoothness "1 linear segments, 3 constant segments";
      input Integer extrapolation "1 hold, 2 last two points, 3 periodic";
      output TimeTable t;
    external "C" t = ModelicaStandardTables_CombiTimeTable_init(tableName, fileName, table, size(table, 1),
      size(table, 2), startTime, columns, size(columns, 1), smoothness, extrapolation);
    end constructor;
    function destructor
      input TimeTable t;
    external "C" ModelicaStandardTables_CombiTimeTable_close(t);
    end destructor;
  end TimeTable;

  function value
    input TimeTable t;
    input Integer icol;
    input Real timeIn;
    input Real next;
    input Real preNext;
    output Real y;
  external "C" y = ModelicaStandardTables_CombiTimeTable_getValue(t, icol, timeIn, next, preNext);
  end value;

  function nextEvent
    input TimeTable t;
    input Real timeIn;
    output Real next;
  external "C" next = ModelicaStandardTables_CombiTimeTable_nextTimeEvent(t, timeIn);
  end nextEvent;

  class Table1D "a table of y over u"
    extends ExternalObject;
    function constructor
      input String tableName;
      input String fileName;
      input Real table[:, :];
      input Integer columns[:];
      input Integer smoothness;
      output Table1D t;
    external "C" t = ModelicaStandardTables_CombiTable1D_init(tableName, fileName, table, size(table, 1),
      size(table, 2), columns, size(columns, 1), smoothness);
    end constructor;
    function destructor
      input Table1D t;
    external "C" ModelicaStandardTables_CombiTable1D_close(t);
    end destructor;
  end Table1D;

  function lookup
    input Table1D t;
    input Integer icol;
    input Real u;
    output Real y;
  external "C" y = ModelicaStandardTables_CombiTable1D_getValue(t, icol, u);
  end lookup;

  block Source "a time table's first column, time events as the MSL's CombiTimeTable takes them"
    parameter Real table[:, :];
    parameter Integer smoothness = 1;
    parameter Integer extrapolation = 1;
    parameter Real startTime = 0;
    parameter String fileName = "NoName";
    parameter String tableName = "NoName";
    output Real y;
  protected
    TimeTable id = TimeTable(tableName, fileName, table, startTime, {2}, smoothness, extrapolation);
    discrete Real next(start = 0, fixed = true);
  equation
    when {time >= pre(next), initial()} then
      next = nextEvent(id, time);
    end when;
    y = value(id, 1, time, next, pre(next));
  end Source;

  // lin: 0 before t = 0.5, then 2 s (s = t - 0.5) up to s = 1, a jump to 5,
  // down to 1 at s = 3, held. con: 1 then 3, period 2.
  // Exact: a = s^2 on [0, 1], 1 + 5 (s - 1) - (s - 1)^2 on [1, 3], 7 + (s - 3)
  // after; b = 4 floor(t / 2) + (tau < 1 ? tau : 1 + 3 (tau - 1)), tau = t mod 2.
  model Integrals
    Source lin(table = [0, 0; 1, 2; 1, 5; 3, 1], smoothness = 1, extrapolation = 1, startTime = 0.5);
    Source con(table = [0, 1; 1, 3; 2, -1], smoothness = 3, extrapolation = 3);
    Real a(start = 0, fixed = true);
    Real b(start = 0, fixed = true);
  equation
    der(a) = lin.y;
    der(b) = con.y;
  end Integrals;

  // y over u = 3 sin(t): u below 0 and above 2 continue the first and the
  // last segment (the C library's extrapolation of a 1-D table).
  model Map
    parameter Real table[:, :] = [0, 0; 1, 1; 2, 4];
    output Real u = 3 * sin(time);
    output Real y = lookup(id, 1, u);
  protected
    Table1D id = Table1D("NoName", "NoName", table, {2}, 1);
  end Map;
  // Akima splines (smoothness = 2, the MSL's ContinuousDerivative) through
  // the same rows: a time table continued by its end slopes after t = 5,
  // and a 1-D table of u = time - 1, continued on both sides.
  model Spline
    parameter Real table[:, :] = [0, 0; 1, 1; 2, 4; 3, 3; 5, 0];
    Source s(table = table, smoothness = 2, extrapolation = 2);
    output Real y = s.y;
    output Real u = time - 1;
    output Real z = lookup(id, 1, u);
    Real area(start = 0, fixed = true) "so that the model has a state to carry sensitivities";
  protected
    Table1D id = Table1D("NoName", "NoName", table, {2}, 2);
  equation
    der(area) = y;
  end Spline;
end Tables;
