model Declared_im
  parameter Real initType_11(fixed=false) =1  "initType_11";
  parameter Real y_start_12(fixed=false) =4  "y_start_12";
  parameter Real initType_21(fixed=false) =0  "initType_21";
  parameter Real y_start_22(fixed=false) =4  "y_start_22";
  DeclaredLib.Doubler Fixed1(initType=initType_11, y_start=y_start_12);
  DeclaredLib.Doubler Free1(initType=initType_21, y_start=y_start_22);
end Declared_im;
