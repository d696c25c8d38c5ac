model FixedLag_im
  parameter Real x_11(fixed=false) =0  "x_11";
  parameter Real y_12(fixed=false) =4  "y_12";
  FixedLag 	FixedLag1(x(start=x_11), y(start=y_12,fixed=true));
end FixedLag_im;
