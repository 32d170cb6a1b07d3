//! Small STEP texts shared by the mapping tests.
#![allow(dead_code)]

use cadre_brep::Model;
use cadre_step::syntax::StepFile;

/// Wraps DATA-section lines into a complete exchange structure.
pub fn step(data: &str) -> String {
    format!(
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n\
         FILE_NAME('t','',(''),(''),'','','');\nFILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\n\
         DATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n"
    )
}

/// Parses and maps a DATA section.
pub fn model(data: &str) -> Model {
    let file = StepFile::parse(step(data).into_bytes()).expect("parses");
    cadre_step::map_file(&file)
}

/// A millimetre / radian context as `#900`, with its units.
pub const MM_CONTEXT: &str = "
#900=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904))
 GLOBAL_UNIT_ASSIGNED_CONTEXT((#901,#902,#903)) REPRESENTATION_CONTEXT('',''));
#901=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#902=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#903=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#901,'distance_accuracy_value','');
";

/// An inch / degree context as `#900`.
pub const INCH_DEGREE_CONTEXT: &str = "
#900=(GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT((#904))
 GLOBAL_UNIT_ASSIGNED_CONTEXT((#905,#907,#903)) REPRESENTATION_CONTEXT('',''));
#901=(LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT(.MILLI.,.METRE.));
#902=(NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.));
#903=(NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT());
#904=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-05),#905,'distance_accuracy_value','');
#905=(CONVERSION_BASED_UNIT('INCH',#906) LENGTH_UNIT() NAMED_UNIT(#908));
#906=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#901);
#907=(CONVERSION_BASED_UNIT('DEGREE',#909) NAMED_UNIT(#908) PLANE_ANGLE_UNIT());
#908=DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.);
#909=PLANE_ANGLE_MEASURE_WITH_UNIT(PLANE_ANGLE_MEASURE(0.0174532925199433),#902);
";

/// A unit cube solid `#80` (0..1 in each axis) in file units, planar faces, line edges.
pub const CUBE: &str = "
#1=CARTESIAN_POINT('',(0.,0.,0.));#2=CARTESIAN_POINT('',(1.,0.,0.));
#3=CARTESIAN_POINT('',(1.,1.,0.));#4=CARTESIAN_POINT('',(0.,1.,0.));
#5=CARTESIAN_POINT('',(0.,0.,1.));#6=CARTESIAN_POINT('',(1.,0.,1.));
#7=CARTESIAN_POINT('',(1.,1.,1.));#8=CARTESIAN_POINT('',(0.,1.,1.));
#11=VERTEX_POINT('',#1);#12=VERTEX_POINT('',#2);#13=VERTEX_POINT('',#3);#14=VERTEX_POINT('',#4);
#15=VERTEX_POINT('',#5);#16=VERTEX_POINT('',#6);#17=VERTEX_POINT('',#7);#18=VERTEX_POINT('',#8);
#20=DIRECTION('',(1.,0.,0.));#21=DIRECTION('',(0.,1.,0.));#22=DIRECTION('',(0.,0.,1.));
#23=VECTOR('',#20,1.);#24=VECTOR('',#21,1.);#25=VECTOR('',#22,1.);
#30=EDGE_CURVE('',#11,#12,#31,.T.);#31=LINE('',#1,#23);
#32=EDGE_CURVE('',#12,#13,#33,.T.);#33=LINE('',#2,#24);
#34=EDGE_CURVE('',#14,#13,#35,.T.);#35=LINE('',#4,#23);
#36=EDGE_CURVE('',#11,#14,#37,.T.);#37=LINE('',#1,#24);
#38=EDGE_CURVE('',#15,#16,#39,.T.);#39=LINE('',#5,#23);
#40=EDGE_CURVE('',#16,#17,#41,.T.);#41=LINE('',#6,#24);
#42=EDGE_CURVE('',#18,#17,#43,.T.);#43=LINE('',#8,#23);
#44=EDGE_CURVE('',#15,#18,#45,.T.);#45=LINE('',#5,#24);
#46=EDGE_CURVE('',#11,#15,#47,.T.);#47=LINE('',#1,#25);
#48=EDGE_CURVE('',#12,#16,#49,.T.);#49=LINE('',#2,#25);
#50=EDGE_CURVE('',#13,#17,#51,.T.);#51=LINE('',#3,#25);
#52=EDGE_CURVE('',#14,#18,#53,.T.);#53=LINE('',#4,#25);
#60=AXIS2_PLACEMENT_3D('',#1,#22,#20);#61=PLANE('',#60);
#62=AXIS2_PLACEMENT_3D('',#5,#22,#20);#63=PLANE('',#62);
#64=AXIS2_PLACEMENT_3D('',#1,#21,#22);#65=PLANE('',#64);
#66=AXIS2_PLACEMENT_3D('',#4,#21,#22);#67=PLANE('',#66);
#68=AXIS2_PLACEMENT_3D('',#1,#20,#21);#69=PLANE('',#68);
#70=AXIS2_PLACEMENT_3D('',#2,#20,#21);#71=PLANE('',#70);
#101=ORIENTED_EDGE('',*,*,#36,.T.);#102=ORIENTED_EDGE('',*,*,#34,.T.);
#103=ORIENTED_EDGE('',*,*,#32,.F.);#104=ORIENTED_EDGE('',*,*,#30,.F.);
#105=EDGE_LOOP('',(#101,#102,#103,#104));#106=FACE_OUTER_BOUND('',#105,.T.);
#107=ADVANCED_FACE('bottom',(#106),#61,.F.);
#111=ORIENTED_EDGE('',*,*,#38,.T.);#112=ORIENTED_EDGE('',*,*,#40,.T.);
#113=ORIENTED_EDGE('',*,*,#42,.F.);#114=ORIENTED_EDGE('',*,*,#44,.F.);
#115=EDGE_LOOP('',(#111,#112,#113,#114));#116=FACE_OUTER_BOUND('',#115,.T.);
#117=ADVANCED_FACE('top',(#116),#63,.T.);
#121=ORIENTED_EDGE('',*,*,#30,.T.);#122=ORIENTED_EDGE('',*,*,#48,.T.);
#123=ORIENTED_EDGE('',*,*,#38,.F.);#124=ORIENTED_EDGE('',*,*,#46,.F.);
#125=EDGE_LOOP('',(#121,#122,#123,#124));#126=FACE_OUTER_BOUND('',#125,.T.);
#127=ADVANCED_FACE('front',(#126),#65,.F.);
#131=ORIENTED_EDGE('',*,*,#34,.F.);#132=ORIENTED_EDGE('',*,*,#52,.T.);
#133=ORIENTED_EDGE('',*,*,#42,.T.);#134=ORIENTED_EDGE('',*,*,#50,.F.);
#135=EDGE_LOOP('',(#131,#132,#133,#134));#136=FACE_OUTER_BOUND('',#135,.T.);
#137=ADVANCED_FACE('back',(#136),#67,.T.);
#141=ORIENTED_EDGE('',*,*,#46,.T.);#142=ORIENTED_EDGE('',*,*,#44,.T.);
#143=ORIENTED_EDGE('',*,*,#52,.F.);#144=ORIENTED_EDGE('',*,*,#36,.F.);
#145=EDGE_LOOP('',(#141,#142,#143,#144));#146=FACE_OUTER_BOUND('',#145,.T.);
#147=ADVANCED_FACE('left',(#146),#69,.F.);
#151=ORIENTED_EDGE('',*,*,#32,.T.);#152=ORIENTED_EDGE('',*,*,#50,.T.);
#153=ORIENTED_EDGE('',*,*,#40,.F.);#154=ORIENTED_EDGE('',*,*,#48,.F.);
#155=EDGE_LOOP('',(#151,#152,#153,#154));#156=FACE_OUTER_BOUND('',#155,.T.);
#157=ADVANCED_FACE('right',(#156),#71,.T.);
#160=CLOSED_SHELL('',(#107,#117,#127,#137,#147,#157));
#80=MANIFOLD_SOLID_BREP('cube',#160);
";
