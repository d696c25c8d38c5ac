// expect: lexical error: unterminated backquoted identifier (Xcos flat dialect)
class unterminated_backquote
	Real `C1.v`(start=0.) "";
	Real `C1.i "";
equation
	(0.001 * der(`C1.v`)) = `C1.i`;
	`C1.i` = (- `C1.v`);
end unterminated_backquote;
