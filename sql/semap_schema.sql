-- SEMAP-style spatial database of the scene graph tracker (PostgreSQL 15, PostGIS 3.3, SFCGAL 1.4).
-- Idempotent: the semap_bridge node runs it at every connection (then sql/semap_relations.sql), as
-- the role that owns the database (scripts/semap-db.sh: semap_bridge, no superuser).
--
-- Boxes are closed POLYHEDRALSURFACE Z built with ST_MakeSolid. The solid flag is kept through
-- ST_Affine and in table columns (not through WKT/WKB), and with it PostGIS' native 3D measures
-- treat the box as a volume: ST_3DDistance of a point inside is 0, ST_3DIntersects of a box
-- inside another is true.
-- The extensions are created once by the database superuser (scripts/semap-db.sh start); the bridge's
-- role cannot, and needs not, create them.
DO $$
BEGIN
  IF (SELECT count(*) FROM pg_extension WHERE extname IN ('postgis', 'postgis_sfcgal')) < 2 THEN
    RAISE EXCEPTION 'semap: the extensions postgis and postgis_sfcgal are missing in database %', current_database()
      USING HINT = 'run scripts/semap-db.sh start DIR PORT, or as a superuser: CREATE EXTENSION postgis; CREATE EXTENSION postgis_sfcgal;';
  END IF;
END
$$;

-- Object descriptions: the class's bounding box in its own frame (extents and as a solid) and a
-- simplified hull (3D convex hull of at most a few hundred mesh vertices, object frame).
CREATE TABLE IF NOT EXISTS object_class (
  name text PRIMARY KEY,
  min_x double precision NOT NULL, min_y double precision NOT NULL, min_z double precision NOT NULL,
  max_x double precision NOT NULL, max_y double precision NOT NULL, max_z double precision NOT NULL,
  box geometry(PolyhedralSurfaceZ) NOT NULL,
  hull geometry
);

-- Object instances (track ids) with their latest pose (x y z, unit quaternion qw qx qy qz, in the
-- scene graph's root frame) and box; `present` is false once the instance left the scene graph.
CREATE TABLE IF NOT EXISTS instance (
  id text PRIMARY KEY,
  class_name text NOT NULL REFERENCES object_class(name),
  parent text NOT NULL DEFAULT 'map',
  first_seen timestamptz NOT NULL,
  last_seen timestamptz NOT NULL,
  present boolean NOT NULL DEFAULT true,
  x double precision NOT NULL, y double precision NOT NULL, z double precision NOT NULL,
  qw double precision NOT NULL, qx double precision NOT NULL, qy double precision NOT NULL,
  qz double precision NOT NULL,
  box geometry(PolyhedralSurfaceZ) NOT NULL
);

-- Fixed instances: the map's furniture and support surfaces (tables, shelves, carts; the bridge's
-- `furniture` file), each with a class of its own named 'furniture:' || id. They are references
-- for the relations like any object, are never marked absent by a frame that misses them, and
-- have no pose history.
ALTER TABLE instance ADD COLUMN IF NOT EXISTS fixed boolean NOT NULL DEFAULT false;
-- The robot whose bridge wrote the instance (its ~robot_id; '' for one robot alone). With several
-- robots in one database each bridge stores its tracks as '<robot>/<track id>', and a robot's
-- frame marks only its own instances absent.
ALTER TABLE instance ADD COLUMN IF NOT EXISTS robot text NOT NULL DEFAULT '';

-- Every pose an instance had, by stamp.
CREATE TABLE IF NOT EXISTS pose_history (
  instance_id text NOT NULL REFERENCES instance(id),
  stamp timestamptz NOT NULL,
  parent text NOT NULL,
  x double precision NOT NULL, y double precision NOT NULL, z double precision NOT NULL,
  qw double precision NOT NULL, qx double precision NOT NULL, qy double precision NOT NULL,
  qz double precision NOT NULL,
  position geometry(PointZ) NOT NULL,
  box geometry(PolyhedralSurfaceZ) NOT NULL,
  arrival bigserial,  -- order in which the rows were written
  PRIMARY KEY (instance_id, stamp)
);
CREATE INDEX IF NOT EXISTS pose_history_stamp ON pose_history (stamp);  -- pruning by age

-- Intervals in which a relation held (until NULL: still holds), kept by semap_update_relations().
CREATE TABLE IF NOT EXISTS relation_history (
  subject text NOT NULL,
  relation text NOT NULL,
  object text NOT NULL,
  mode text NOT NULL,
  since timestamptz NOT NULL,
  until timestamptz,
  PRIMARY KEY (subject, relation, object, mode, since)
);
CREATE INDEX IF NOT EXISTS relation_history_open ON relation_history (subject, relation, object, mode)
  WHERE until IS NULL;

-- The unit cube [0,1]^3 as a solid (faces as SFCGAL's ST_Extrude orients them).
CREATE OR REPLACE FUNCTION semap_unit_cube() RETURNS geometry LANGUAGE sql IMMUTABLE AS $$
  SELECT ST_MakeSolid('POLYHEDRALSURFACE Z (((0 0 0,0 1 0,1 1 0,1 0 0,0 0 0)),((0 0 1,1 0 1,1 1 1,0 1 1,0 0 1)),
    ((0 0 0,0 0 1,0 1 1,0 1 0,0 0 0)),((0 1 0,0 1 1,1 1 1,1 1 0,0 1 0)),((1 1 0,1 1 1,1 0 1,1 0 0,1 1 0)),
    ((1 0 0,1 0 1,0 0 1,0 0 0,1 0 0)))'::geometry)
$$;

-- The axis-aligned box [x0,x1] x [y0,y1] x [z0,z1] as a solid: the unit cube scaled and moved
-- (ST_Scale and ST_Translate keep the solid flag; building it with ST_Extrude costs 200x more).
-- A flat side is given 1 um.
CREATE OR REPLACE FUNCTION semap_aabb(x0 float8, y0 float8, z0 float8, x1 float8, y1 float8, z1 float8)
RETURNS geometry LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT ST_Translate(ST_Scale(semap_unit_cube(), greatest(x1 - x0, 1e-6), greatest(y1 - y0, 1e-6),
                               greatest(z1 - z0, 1e-6)), x0, y0, z0)
$$;

-- g moved by the pose (translation x y z, unit quaternion qw qx qy qz): world = R g + t.
CREATE OR REPLACE FUNCTION semap_place(g geometry, x float8, y float8, z float8,
                                       qw float8, qx float8, qy float8, qz float8)
RETURNS geometry LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT ST_Affine(g,
    1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw),     2 * (qx * qz + qy * qw),
    2 * (qx * qy + qz * qw),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw),
    2 * (qx * qz - qy * qw),     2 * (qy * qz + qx * qw),     1 - 2 * (qx * qx + qy * qy),
    x, y, z)
$$;

-- The inverse of semap_place: world geometry into the frame of the pose. R^T (g - t).
CREATE OR REPLACE FUNCTION semap_unplace(g geometry, x float8, y float8, z float8,
                                         qw float8, qx float8, qy float8, qz float8)
RETURNS geometry LANGUAGE sql IMMUTABLE STRICT AS $$
  SELECT ST_Affine(ST_Translate(g, -x, -y, -z),
    1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy + qz * qw),     2 * (qx * qz - qy * qw),
    2 * (qx * qy - qz * qw),     1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz + qx * qw),
    2 * (qx * qz + qy * qw),     2 * (qy * qz - qx * qw),     1 - 2 * (qx * qx + qy * qy),
    0, 0, 0)
$$;

-- The 3D convex hull of some points (SFCGAL), NULL when they are degenerate (flat, too few).
CREATE OR REPLACE FUNCTION semap_hull(points geometry) RETURNS geometry LANGUAGE plpgsql IMMUTABLE AS $$
BEGIN
  RETURN ST_3DConvexHull(points);
EXCEPTION WHEN OTHERS THEN
  RETURN NULL;
END
$$;
