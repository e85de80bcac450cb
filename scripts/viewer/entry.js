// The parts of three.js the HTML report's 3D view uses (geomcheck/report/templates/view3d.js),
// bundled by build.sh into one script that defines the global THREE.
export {
  AmbientLight, Box3, BoxGeometry, BufferAttribute, BufferGeometry, Color, CylinderGeometry,
  DirectionalLight, EdgesGeometry, Group, HemisphereLight, LineBasicMaterial, LineDashedMaterial,
  LineSegments, Matrix4, Mesh, MeshLambertMaterial, PerspectiveCamera, Quaternion, Scene,
  Sphere, SphereGeometry, Vector3, WebGLRenderer, DoubleSide
} from 'three';
export { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
