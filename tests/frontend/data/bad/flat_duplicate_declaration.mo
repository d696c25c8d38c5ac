// expect: duplicate declaration of `C1.v` in the flat class (Xcos flat dialect)
class flat_duplicate_declaration
	Real `C1.v`(start=0.) "";
	Real `C1.v` "";
equation
	der(`C1.v`) = (- `C1.v`);
end flat_duplicate_declaration;
